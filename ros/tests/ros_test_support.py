"""What the ROS node's test scripts share: skipping and failing as CTest reads it,
a private master on a free loopback port, waiting, and stopping what was started."""
import os
import shutil
import socket
import subprocess
import sys
import time

SKIP = 77  # CTest's SKIP_RETURN_CODE


def skip(why):
    print(f"SKIP: {why}")
    sys.exit(SKIP)


def fail(why):
    print(f"FAIL: {why}")
    sys.exit(1)


try:
    import rosgraph
    import rospy  # noqa: F401 (the scripts' own import is then sure to work)
except ImportError as e:
    skip(f"ROS 1's Python packages are not installed ({e}): scripts/setup.sh --ros")


def require_node(build):
    """Skips unless build has the node and ROS's master is installed."""
    if not os.path.isfile(os.path.join(build, "sgslam_ros")):
        skip(f"{build}/sgslam_ros is not built (ROS 1 was not installed at configure time: scripts/setup.sh --ros)")
    if not shutil.which("rosmaster"):
        skip("rosmaster is not installed (scripts/setup.sh --ros)")


def wait_for(predicate, seconds, what):
    until = time.time() + seconds
    while time.time() < until:
        if predicate():
            return
        time.sleep(0.1)
    fail(f"timed out after {seconds} s waiting for {what}")


def start_master(work):
    """A master on a free loopback port, this process's environment pointed at it
    (and so the children's); returns its process."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    os.environ.update(ROS_MASTER_URI=f"http://127.0.0.1:{port}", ROS_IP="127.0.0.1",
                      ROS_HOME=os.path.join(work, "ros_home"))
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    wait_for(lambda: rosgraph.Master("/test").is_online(), 20, "the ROS master")
    return master


def stop(procs):
    """Ends what is still running, newest first."""
    for p in reversed(procs):
        if p.poll() is None:
            p.terminate()
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
