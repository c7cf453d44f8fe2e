#!/usr/bin/python3
"""Bad input to the ROS node: each case gets a clear log line and the node goes on.

A private master on a free loopback port and the node, fed by this script from a
synthetic sequence: no camera_info at all, then in turn a colour encoding it cannot
read, a depth encoding with no known scale, colour and depth of different sizes,
images of another size than the camera, a duplicated and an out-of-order stamp, and
a publisher that stops for 3 s and resumes. Between the cases, good frames, and the
node must publish their poses. At the end, Ctrl-C: stats.json counts the refused
frames and the node exits as stopped by SIGINT.

    ros_bad_input.py --build BUILD [--keep DIR]

Exits 77 (CTest's skip) with a message when ROS 1 or the node is missing.
"""
import argparse
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time

from ros_test_support import fail, require_node, start_master, stop, wait_for

try:
    import cv2
    import numpy as np
    import rospy
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import Image
except ImportError as e:
    from ros_test_support import skip
    skip(f"ROS 1's Python packages or python3-opencv are not installed ({e}): scripts/setup.sh --ros")


def image_msg(array, encoding, stamp):
    m = Image()
    m.header.stamp = stamp
    m.header.frame_id = "camera"
    m.height, m.width = array.shape[:2]
    m.encoding = encoding
    m.is_bigendian = 0
    m.step = array.strides[0]
    m.data = array.tobytes()
    return m


class Feeder:
    """Publishes frames of a TUM-layout folder, with stamps of its own choosing."""

    def __init__(self, seq):
        self.rgb_pub = rospy.Publisher("/camera/rgb/image_color", Image, queue_size=10)
        self.depth_pub = rospy.Publisher("/camera/depth/image", Image, queue_size=10)
        names = [l.split() for l in open(os.path.join(seq, "associations.txt")) if l.strip() and l[0] != "#"]
        self.frames = [(os.path.join(seq, n[1]), os.path.join(seq, n[3])) for n in names]
        self.next = 0
        self.t = 100.0  # s: the stamps this feeder gives

    def images(self):
        rgb_path, depth_path = self.frames[self.next % len(self.frames)]
        self.next += 1
        bgr = cv2.imread(rgb_path, cv2.IMREAD_COLOR)
        depth = cv2.imread(depth_path, cv2.IMREAD_UNCHANGED).astype(np.float32) / 5000.0
        depth[depth == 0] = np.nan
        return bgr, depth

    def send(self, bgr, depth, rgb_encoding="bgr8", depth_encoding="32FC1", stamp=None, advance=True):
        if advance:
            self.t += 1.0 / 30
        t = rospy.Time.from_sec(self.t if stamp is None else stamp)
        self.rgb_pub.publish(image_msg(bgr, rgb_encoding, t))
        self.depth_pub.publish(image_msg(depth, depth_encoding, t))
        time.sleep(1.0 / 30)

    def good(self, n):
        for _ in range(n):
            self.send(*self.images())


def cases(feeder, poses, log_path):
    """Each bad case, then good frames whose poses must come; returns the log lines expected."""
    def expect_poses_after(what):
        before = len(poses)
        feeder.good(8)
        wait_for(lambda: len(poses) >= before + 6, 30, f"poses after {what} (node log: {log_path})")

    bgr, depth = feeder.images()
    feeder.send(cv2.cvtColor(bgr, cv2.COLOR_BGR2YUV_YUY2) if hasattr(cv2, "COLOR_BGR2YUV_YUY2") else bgr[:, :, :2],
                depth, rgb_encoding="yuv422")
    expect_poses_after("a colour encoding it cannot read")
    feeder.send(bgr, (np.nan_to_num(depth) * 50).astype(np.uint8), depth_encoding="8UC1")
    expect_poses_after("a depth encoding of unknown scale")
    feeder.send(bgr, np.ascontiguousarray(depth[::2, ::2]))
    expect_poses_after("colour and depth of different sizes")
    feeder.send(np.ascontiguousarray(bgr[::2, ::2]), np.ascontiguousarray(depth[::2, ::2]))
    expect_poses_after("images of another size than the camera")
    feeder.send(bgr, depth, stamp=feeder.t, advance=False)  # the last good frame's stamp again
    expect_poses_after("a duplicated stamp")
    feeder.send(bgr, depth, stamp=feeder.t - 1.0, advance=False)
    expect_poses_after("a stamp out of order")
    time.sleep(3.0)  # the publisher stops
    feeder.t += 3.0
    expect_poses_after("a publisher that stopped and resumed")
    return ["no camera_info on /camera/rgb/camera_info", "colour image encoding 'yuv422'",
            "depth image encoding '8UC1'", "differ in size", "the camera is 640x480",
            "its stamp is the same as the last frame's", "its stamp is before the last frame's",
            "images resumed after a gap of 3.", "frames are usable again"]


def refused_outputs(node, work, seq):
    """~out where the node must not write: refused at start, naming both paths (#47)."""
    config = os.path.join(work, "used", "config_used.yaml")
    os.makedirs(os.path.dirname(config), exist_ok=True)
    shutil.copy(os.path.join(seq, "sgslam.yaml"), config)
    for params, expected in ((["_out:=/"], "~out /: / is a system folder"),
                             ([f"_out:={os.path.dirname(config)}", f"_config:={config}"],
                              "it is read, and writing would destroy it")):
        p = subprocess.run([node, "__name:=sgslam_refused", "_mode:=none", *params], capture_output=True, text=True,
                           timeout=60)
        if p.returncode != 1 or expected not in p.stderr:
            fail(f"sgslam_ros {' '.join(params)}: exit {p.returncode}, expected 1 and '{expected}':\n{p.stderr}")
        print(f"refused: {' '.join(params)}: {p.stderr.strip().splitlines()[-1][:160]}")
    if open(config).read() != open(os.path.join(seq, "sgslam.yaml")).read():
        fail(f"{config} was rewritten")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--keep", help="keep the work folder here")
    args = ap.parse_args()
    build = os.path.abspath(args.build)
    sgslam, node = os.path.join(build, "sgslam"), os.path.join(build, "sgslam_ros")
    require_node(build)
    work = os.path.abspath(args.keep or tempfile.mkdtemp(prefix="sgslam-ros-bad-"))
    os.makedirs(work, exist_ok=True)
    seq, out, log_path = os.path.join(work, "seq"), os.path.join(work, "out"), os.path.join(work, "node.log")
    if not os.path.isfile(os.path.join(seq, "associations.txt")):
        subprocess.run([sgslam, "synth", "--out", seq, "--preset", "static", "--frames", "90", "--force"], check=True,
                       capture_output=True)
    procs = []
    try:
        procs.append(start_master(work))
        refused_outputs(node, work, seq)
        shutil.rmtree(out, ignore_errors=True)
        node_proc = subprocess.Popen([node, "__name:=sgslam", f"_out:={out}", "_mode:=none", "_camera_info_wait:=0.3",
                                      "_queue_size:=100",  # every good frame is tracked, however loaded the machine
                                      f"_config:={os.path.join(seq, 'sgslam.yaml')}"],
                                     stdout=open(log_path, "w"), stderr=subprocess.STDOUT)
        procs.append(node_proc)
        rospy.init_node("bad_input", anonymous=True, disable_signals=True)
        poses = []
        rospy.Subscriber("/sgslam/odometry", Odometry, lambda m: poses.append(m.header.stamp.to_sec()), queue_size=100)
        feeder = Feeder(seq)
        wait_for(lambda: feeder.rgb_pub.get_num_connections() > 0 and feeder.depth_pub.get_num_connections() > 0,
                 20, "the node to subscribe")
        feeder.good(30)  # no camera_info: the config's camera after 0.3 s
        wait_for(lambda: len(poses) >= 5, 30, f"the first poses (node log: {log_path})")
        expected = cases(feeder, poses, log_path)
        node_proc.send_signal(signal.SIGINT)
        code = node_proc.wait(timeout=60)
    finally:
        stop(procs)
        rospy.signal_shutdown("done")
    log = open(log_path).read()
    missing = [e for e in expected if e not in log]
    if missing:
        fail(f"the node's log ({log_path}) has no line with: {missing}")
    if code != 128 + signal.SIGINT:
        fail(f"sgslam_ros exited {code} on SIGINT, expected {128 + signal.SIGINT}")
    stats = json.load(open(os.path.join(out, "stats.json")))
    if stats["live"]["refused"] < 6 or stats["ended"] != "interrupted by SIGINT":
        fail(f"stats.json: refused {stats['live']['refused']} (6 bad frames sent), ended {stats['ended']!r}")
    print(f"{len(poses)} poses; {stats['live']['refused']} frames refused, each case logged:")
    for e in expected:
        print(f"  {next(l for l in log.splitlines() if e in l).strip()[:160]}")
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    print("PASS")


if __name__ == "__main__":
    main()
