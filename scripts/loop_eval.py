#!/usr/bin/env python3
"""Loop-closing figures of one `sgslam run` on a sequence with ground truth:
  - the first revisit: the first frame whose ground-truth camera is within 0.5 m and
    30 degrees (optical axis) of its pose at least 10 s earlier;
  - the first loop closed (stats.json) and how many keyframes tracking made between
    the revisit and it (frames.csv);
  - the end-to-start error: the estimated motion from the first to the last tracked
    frame against the ground truth's (translation m, rotation deg).
  scripts/loop_eval.py DATASET RUN_OUT"""
import json
import math
import os
import sys


def read_poses(path):
    out = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = [float(x) for x in line.split()[:8]]
            out.append((v[0], v[1:4], v[4:8]))
    return sorted(out)


def qmul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz)


def qconj(q):
    return (-q[0], -q[1], -q[2], q[3])


def qrot(q, v):
    x, y, z, _ = qmul(qmul(q, (v[0], v[1], v[2], 0.0)), qconj(q))
    return (x, y, z)


def relative(a, b):
    """T_a^-1 * T_b for poses (t, q) in the world."""
    qa_inv = qconj(a[2])
    d = [b[1][i] - a[1][i] for i in range(3)]
    return qrot(qa_inv, d), qmul(qa_inv, b[2])


def angle_deg(q):
    return math.degrees(2 * math.acos(min(1.0, abs(q[3]))))


def nearest(poses, t):
    best = min(poses, key=lambda p: abs(p[0] - t))
    return best if abs(best[0] - t) < 0.02 else None


def first_revisit(gt):
    for i, (t, p, q) in enumerate(gt):
        axis = qrot(q, (0, 0, 1))
        for t0, p0, q0 in gt[:i]:
            if t - t0 < 10:
                break
            if math.dist(p, p0) > 0.5:
                continue
            a0 = qrot(q0, (0, 0, 1))
            if sum(x * y for x, y in zip(axis, a0)) > math.cos(math.radians(30)):
                return t
    return None


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    data, out = sys.argv[1:]
    gt = read_poses(os.path.join(data, "groundtruth.txt"))
    est = read_poses(os.path.join(out, "trajectory.txt"))
    stats = json.load(open(os.path.join(out, "stats.json"), encoding="utf-8"))
    revisit = first_revisit(gt[::3])
    closed = stats.get("loop", {}).get("closed", [])
    print(f"first revisit at t = {revisit:.3f}" if revisit else "no revisit in the ground truth")
    if closed:
        loop_t = float(closed[0]["timestamp"])
        with open(os.path.join(out, "frames.csv"), encoding="utf-8") as f:
            header = f.readline().strip().split(",")
            ti, ki = header.index("timestamp"), header.index("keyframe")
            made = sum(1 for row in (l.split(",") for l in f)
                       if revisit is not None and revisit <= float(row[ti]) <= loop_t and row[ki] == "1")
        print(f"first loop closed at t = {loop_t:.3f} (keyframe {closed[0].get('keyframe')}), "
              f"{made} keyframes after the revisit; {len(closed)} loop(s) closed")
    else:
        print("no loop closed")
    a, b = est[0], est[-1]
    ga, gb = nearest(gt, a[0]), nearest(gt, b[0])
    if ga and gb:
        te, qe = relative(a, b)
        tg, qg = relative(ga, gb)
        # error = rel_gt^-1 * rel_est
        dt = qrot(qconj(qg), [te[i] - tg[i] for i in range(3)])
        dq = qmul(qconj(qg), qe)
        print(f"end-to-start error: {math.sqrt(sum(x * x for x in dt)):.4f} m, {angle_deg(dq):.3f} deg")


if __name__ == "__main__":
    main()
