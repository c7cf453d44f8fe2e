#!/usr/bin/env python3
"""Soak: one long `sgslam run` in parallel mode (every thread on) over a synthetic
sequence played again and again, to see that memory grows no faster than the map,
that frames do not slow down over time and that the run ends cleanly.

The `loop` preset is a closed path whose last frame is its first, so its frames
repeated (the lists rewritten with shifted timestamps; the images are linked, not
copied) make one continuous walk of any length.
  scripts/soak.py [--frames 20000] [--detector dnn|file] [--work DIR] [-- options for sgslam run]
Prints: frames tracked, the map's keyframes and points (after 1 000 frames and at the
end), resident memory then and its growth per keyframe added (MiB, least squares of
frames.csv's rss_mib on map_keyframes), median frame ms of the first and last 1 000
frames, and the process's thread count while running."""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def data_lines(path):
    with open(path, encoding="utf-8") as f:
        return [l.split() for l in f if l.strip() and not l.startswith("#")]


def render_base(sgslam, base):
    if os.path.exists(os.path.join(base, "associations.txt")):
        return
    r = subprocess.run([sgslam, "-q", "synth", "--preset", "loop", "--out", base], text=True,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.exit(f"error: sgslam synth failed ({r.returncode}):\n{r.stdout[-2000:]}")


def write_repeated(base, seq, frames):
    """The base sequence's frames 0..n-2 again and again (frame n-1 is frame 0's pose)."""
    os.makedirs(seq, exist_ok=True)
    for d in ("rgb", "depth"):
        link = os.path.join(seq, d)
        if not os.path.islink(link):
            os.symlink(os.path.join(base, d), link)
    with open(os.path.join(base, "sgslam.yaml"), encoding="utf-8") as f:
        config = f.read()
    with open(os.path.join(seq, "sgslam.yaml"), "w", encoding="utf-8") as f:
        f.write(config)
    assoc = data_lines(os.path.join(base, "associations.txt"))
    gt = data_lines(os.path.join(base, "groundtruth.txt"))
    lap = len(assoc) - 1
    period = float(assoc[-1][0]) - float(assoc[0][0])
    out = {"associations.txt": [], "rgb.txt": [], "depth.txt": [], "groundtruth.txt": []}
    for i in range(frames):
        k, j = divmod(i, lap)
        a = assoc[j]
        t_rgb, t_depth = float(a[0]) + k * period, float(a[2]) + k * period
        out["associations.txt"].append(f"{t_rgb:.6f} {a[1]} {t_depth:.6f} {a[3]}")
        out["rgb.txt"].append(f"{t_rgb:.6f} {a[1]}")
        out["depth.txt"].append(f"{t_depth:.6f} {a[3]}")
        if j < len(gt):
            g = gt[j]
            out["groundtruth.txt"].append(f"{float(g[0]) + k * period:.6f} " + " ".join(g[1:]))
    out["detections.txt"] = ["# detections: timestamp class_id score x0 y0 x1 y1 class_name (box in px)"]
    boxes = data_lines(os.path.join(base, "detections.txt"))
    for k in range((frames + lap - 1) // lap):
        out["detections.txt"] += [f"{float(b[0]) + k * period:.6f} " + " ".join(b[1:]) for b in boxes]
    for name, lines in out.items():
        with open(os.path.join(seq, name), "w", encoding="utf-8") as f:
            f.write("\n".join(lines) + "\n")


def run_watched(cmd, log):
    """Runs cmd, sampling its thread count twice a second; returns (exit status, samples)."""
    samples = []
    with open(log, "w", encoding="utf-8") as out:
        p = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT)
        while p.poll() is None:
            try:
                with open(f"/proc/{p.pid}/status", encoding="utf-8") as f:
                    samples += [int(l.split()[1]) for l in f if l.startswith("Threads:")]
            except OSError:
                pass
            time.sleep(0.5)
        return p.returncode, samples


def slope(xs, ys):
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else float("nan")


def report(out, threads, status, wall, log):
    if not os.path.exists(os.path.join(out, "frames.csv")):
        with open(log, encoding="utf-8") as f:
            sys.exit(f"error: the run failed ({status}) and wrote no frames.csv:\n" + f.read()[-2000:])
    with open(os.path.join(out, "frames.csv"), encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(out, "stats.json"), encoding="utf-8") as f:
        stats = json.load(f)
    n = len(rows)
    head, tail = rows[:1000], rows[-1000:]
    grown = rows[1000:] if n > 2000 else rows
    kf = [int(r["map_keyframes"]) for r in grown]
    rss = [float(r["rss_mib"]) for r in grown]
    ms = lambda rs: statistics.median(float(r["total_ms"]) for r in rs)
    steady = threads[len(threads) // 10:-4] or threads
    print(f"exit status {status}, ended: {stats.get('ended')}, wall {wall:.0f} s; threads: "
          f"{min(steady)}-{max(steady)} while running (after the first tenth), {threads[-1]} in the last sample")
    print(f"frames {n}, tracked {stats['tracked']}, lost {stats['lost']}")
    at = rows[min(999, n - 1)]
    print(f"after frame {int(at['index']) + 1}: {at['map_keyframes']} keyframes, {at['map_points']} points, "
          f"{float(at['rss_mib']):.0f} MiB")
    print(f"at the end: {rows[-1]['map_keyframes']} keyframes, {rows[-1]['map_points']} points, "
          f"{float(rows[-1]['rss_mib']):.0f} MiB (peak {stats['peak_rss_mib']:.0f} MiB)")
    per_kf = slope(kf, rss) if len(set(kf)) > 1 else None
    print("memory growth: " + (f"{per_kf:.3f} MiB per map keyframe; " if per_kf is not None else "") +
          f"{(rss[-1] - rss[0]) / max(1, len(rss)) * 1000:.2f} MiB per 1000 frames")
    flat = [r for r in grown if int(r["map_keyframes"]) == kf[-1]]
    if len(flat) > 1000:
        print(f"while the map held its final size ({len(flat)} frames): "
              f"{(float(flat[-1]['rss_mib']) - float(flat[0]['rss_mib'])) / len(flat) * 1000:.2f} MiB per 1000 frames")
    print(f"median frame ms: first 1000 {ms(head):.1f}, last 1000 {ms(tail):.1f} "
          f"(ratio {ms(tail) / ms(head):.2f}); fps {stats['fps']:.1f}")
    if "ate" in stats:
        print(f"ATE {stats['ate'].get('rmse', float('nan')):.4f} m")


def main():
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--frames", type=int, default=20000)
    p.add_argument("--detector", choices=("dnn", "file"), default="dnn",
                   help="the real detector (default), or the sequence's ground-truth boxes replayed")
    p.add_argument("--sgslam", default=os.path.join(HERE, "..", "build", "sgslam"))
    p.add_argument("--work", help="folder for the sequence and the run (default: a temporary one); "
                                  "the rendered loop is kept there and reused")
    a = p.parse_args(argv)
    if a.frames < 2000:
        sys.exit("error: --frames must be at least 2000 (the first and last 1000 are compared)")
    work = os.path.abspath(a.work or tempfile.mkdtemp(prefix="sgslam-soak-"))
    base, seq, out = (os.path.join(work, d) for d in ("loop", f"soak{a.frames}", "out"))
    render_base(a.sgslam, base)
    write_repeated(base, seq, a.frames)
    start = time.monotonic()
    log = os.path.join(work, "run.log")
    cmd = [a.sgslam, "run", "--dataset", seq, "--out", out]
    if a.detector == "dnn":  # on top of the sequence's own sgslam.yaml, which replays its boxes
        config = os.path.join(work, "dnn.yaml")
        with open(config, "w", encoding="utf-8") as f:
            f.write("detector:\n  backend: dnn\n")
        cmd += ["--config", config]
    status, threads = run_watched(cmd + extra, log)
    report(out, threads, status, time.monotonic() - start, log)
    return 0 if status == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
