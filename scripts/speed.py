#!/usr/bin/env python3
"""Speed benchmark: `sgslam run` in several modes on the same sequences, alternated
(mode order rotated every repeat) so that a shared machine's noise falls on all of
them alike, and the medians over the repeats as a Markdown table.

  scripts/speed.sh [--modes none,sg] [--variant LABEL="OPTIONS"]... [--repeats 3]
                   [--sequences tum_fr1_rpy,dyn_dev,walkers:1] [--realtime]
                   [--sgslam build/sgslam] [--work DIR] [--markdown FILE]
                   [-- more options for every sgslam run]

--modes M1,M2 runs `--mode M` for each; --variant adds a run with its own options
(`--variant sg-stride3="--mode sg --config my.yaml"`); with --variant given, only
the variants run unless --modes is given too. A variant's options may start with
@PATH, another sgslam binary for it (`--variant before="@/tmp/old/sgslam --mode sg"`):
two builds compared in one sitting, alternated.

A sequence is a folder, a folder under the shared data ($SGSLAM_SHARED_DIR/data or
../shared/data), or PRESET[:SEED] for a generated one (rendered once into --work).
A sequence with ground-truth masks runs without them (a linked view): scoring the
rejection against them is evaluation work on the tracking thread, not SLAM.
Per run: end-to-end fps (frames over the run's wall time, stats.json), the median
frame ms on the tracking thread, CPU ms a frame (user+sys of the whole process over
its frames: less noisy than wall time on a shared machine), peak RSS and the ATE;
with --realtime also the frames dropped and the latency from frame time to pose
(median and 95th percentile) when stats.json reports them. The table gives the
medians over the repeats, and the ratio of each mode's CPU ms a frame to the first
mode's; the mover tracker's median ms a frame (stats.json tracks) where it ran."""
import argparse
import json
import shlex
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def shared_data():
    env = os.environ.get("SGSLAM_SHARED_DIR")
    return os.path.join(env, "data") if env else os.path.join(ROOT, "..", "shared", "data")


def without_masks(folder, work):
    """The folder itself, or, when it has ground-truth masks (mask.txt), a view of it
    without them (links to everything else): `sgslam run` scores its rejection
    against the masks on the tracking thread, which is evaluation, not SLAM (3.7 CPU
    ms a frame on dyn_dev, measured 2026-12-05)."""
    if not os.path.exists(os.path.join(folder, "mask.txt")):
        return folder
    view = os.path.join(work, "without-masks", os.path.basename(folder.rstrip("/")))  # the name picks the camera
    os.makedirs(view, exist_ok=True)
    for entry in os.listdir(folder):
        if entry in ("mask.txt", "mask") or os.path.lexists(os.path.join(view, entry)):
            continue
        os.symlink(os.path.join(folder, entry), os.path.join(view, entry))
    return view


def resolve(sgslam, name, work):
    """The sequence folder for a name: a folder, a shared one, or a rendered preset
    (without its ground-truth masks: see without_masks)."""
    for folder in (name, os.path.join(shared_data(), name)):
        if os.path.isdir(folder):
            return without_masks(os.path.abspath(folder), work)
    preset, _, seed = name.partition(":")
    if preset in ("static", "walkers", "objects", "rpy", "loop", "repeat", "degenerate"):
        out = os.path.join(work, f"{preset}-{seed or 1}")
        if not os.path.exists(os.path.join(out, "rgb.txt")):
            r = subprocess.run([sgslam, "-q", "synth", "--preset", preset, "--seed", seed or "1", "--out", out,
                                "--force"], text=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
            if r.returncode != 0:
                sys.exit(f"speed: sgslam synth --preset {preset} failed ({r.returncode}):\n{r.stdout[-2000:]}")
        return without_masks(out, work)
    sys.exit(f"speed: sequence '{name}' is not a folder, not in {shared_data()}, and not a synth preset")


def run_once(sgslam, dataset, options, out, realtime, extra):
    cmd = [sgslam, "-q", "run", "--dataset", dataset, "--out", out] + options + (["--realtime"] if realtime else [])
    cmd += extra
    start = time.monotonic()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    output = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.monotonic() - start
    if proc.returncode != 0:
        sys.exit(f"speed: {' '.join(cmd)} failed ({proc.returncode}):\n{output[-3000:]}")
    with open(os.path.join(out, "stats.json"), encoding="utf-8") as f:
        stats = json.load(f)
    frames = max(1, stats["frames"])
    row = {
        "fps": stats["fps"],
        "frame_ms": stats["median_ms"]["frame"],
        "cpu_ms": 1000.0 * (usage.ru_utime + usage.ru_stime) / frames,
        "rss": stats["peak_rss_mib"],
        "ate": stats.get("ate", {}).get("rmse"),
        "wall": wall,
        "movers_ms": stats.get("tracks", {}).get("median_ms"),
    }
    live = stats.get("live")
    if live:
        row["dropped"] = live.get("dropped")
        row["latency_ms"] = live.get("median_latency_ms")
        row["latency95_ms"] = live.get("p95_latency_ms")
    return row


def median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def fmt(v, digits):
    return "-" if v is None else f"{v:.{digits}f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--modes", help="default none,sg (without --variant)")
    ap.add_argument("--variant", action="append", default=[], metavar='LABEL="OPTIONS"',
                    help="a run with these sgslam run options, under this label (repeatable)")
    ap.add_argument("--sequences", default="tum_fr1_rpy,dyn_dev,walkers:1")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--realtime", action="store_true")
    ap.add_argument("--sgslam", default=os.path.join(ROOT, "build", "sgslam"))
    ap.add_argument("--work", help="scratch folder (default: a temporary one, removed)")
    ap.add_argument("--markdown", help="also write the table to this file")
    ap.add_argument("extra", nargs="*", help="after --: options for sgslam run")
    a = ap.parse_args()
    if not os.access(a.sgslam, os.X_OK):
        sys.exit(f"speed: no sgslam binary at {a.sgslam} (build first, or --sgslam PATH)")
    if a.repeats < 1:
        sys.exit("speed: --repeats must be at least 1")
    runs_of = {}  # label -> options, in order
    binary_of = {}  # label -> its sgslam binary, when not --sgslam
    if a.modes or not a.variant:
        for m in (a.modes or "none,sg").split(","):
            if m:
                runs_of[m] = ["--mode", m]
    for v in a.variant:
        label, eq, options = v.partition("=")
        if not eq or not label:
            sys.exit(f"speed: --variant {v!r}: expected LABEL=\"OPTIONS\"")
        words = shlex.split(options)
        if words and words[0].startswith("@"):
            binary_of[label] = words.pop(0)[1:]
            if not os.access(binary_of[label], os.X_OK):
                sys.exit(f"speed: --variant {label}: no sgslam binary at {binary_of[label]!r}")
        runs_of[label] = words
    modes = list(runs_of)
    tmp = None if a.work else tempfile.TemporaryDirectory(prefix="sgslam-speed.")
    work = a.work or tmp.name
    os.makedirs(work, exist_ok=True)
    sequences = [(name, resolve(a.sgslam, name, work)) for name in a.sequences.split(",") if name]
    runs = {}
    for rep in range(a.repeats):
        for name, path in sequences:
            order = modes[rep % len(modes):] + modes[:rep % len(modes)]
            for mode in order:
                row = run_once(binary_of.get(mode, a.sgslam), path, runs_of[mode], os.path.join(work, "out"), a.realtime, a.extra)
                runs.setdefault((name, mode), []).append(row)
                print(f"speed: {name} {mode} #{rep + 1}: {row['fps']:.1f} fps, {row['cpu_ms']:.1f} CPU ms/frame, "
                      f"ATE {fmt(row['ate'], 4)}", file=sys.stderr, flush=True)
    head = ("| sequence | run | fps | frame ms | movers ms | CPU ms/frame | CPU ratio | peak MiB | ATE m |"
            + (" dropped | latency ms (median / p95) |" if a.realtime else ""))
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for name, _ in sequences:
        base = median(r["cpu_ms"] for r in runs[(name, modes[0])])
        for mode in modes:
            rs = runs[(name, mode)]
            cpu = median(r["cpu_ms"] for r in rs)
            line = (f"| {name} | {mode} | {fmt(median(r['fps'] for r in rs), 1)} | "
                    f"{fmt(median(r['frame_ms'] for r in rs), 1)} | {fmt(median(r['movers_ms'] for r in rs), 2)} | "
                    f"{fmt(cpu, 1)} | "
                    f"{fmt(cpu / base if base else None, 2)} | {fmt(median(r['rss'] for r in rs), 0)} | "
                    f"{fmt(median(r['ate'] for r in rs), 4)} |")
            if a.realtime:
                line += (f" {fmt(median(r.get('dropped') for r in rs), 0)} | "
                         f"{fmt(median(r.get('latency_ms') for r in rs), 1)} / "
                         f"{fmt(median(r.get('latency95_ms') for r in rs), 1)} |")
            lines.append(line)
    table = "\n".join(lines)
    how = " ".join(shlex.quote(x) for x in sys.argv[1:])
    note = (f"\nMedians of {a.repeats} alternated runs, {time.strftime('%Y-%m-%d')}, "
            f"`scripts/speed.sh {how}"
            f"`; CPU ratio: CPU ms a frame over {modes[0]}'s.")
    print(table + "\n" + note)
    if a.markdown:
        with open(a.markdown, "w", encoding="utf-8") as f:
            f.write(table + "\n" + note + "\n")


if __name__ == "__main__":
    main()
