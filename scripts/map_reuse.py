#!/usr/bin/env python3
"""Map reuse, measured: maps the first N frames of a sequence and saves the map,
then runs the rest of it (or another sequence of the same place, --then) from that
map, and prints the share of frames localised, the ATE of those frames in the
map's frame (the alignment is fitted on the mapping run only: `sgslam eval
--align-with`), the keyframes added, the map file's size and the load time.
  scripts/map_reuse.py --dataset ../shared/data/tum_fr1_rpy --split 350 [--localize]
  scripts/map_reuse.py --dataset ../shared/data/tum_fr1_rpy --then ../shared/data/dyn_dev --localize
Options after -- go to both `sgslam run`s (e.g. -- --mode sg --sequential)."""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        sys.exit(f"error: {' '.join(cmd)} failed ({r.returncode}):\n{r.stdout[-3000:]}")
    return r.stdout


def frame_count(seq):
    name = "associations.txt" if os.path.exists(os.path.join(seq, "associations.txt")) else "rgb.txt"
    with open(os.path.join(seq, name), encoding="utf-8") as f:
        return sum(1 for l in f if l.strip() and not l.startswith("#"))


def main():
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--dataset", required=True, help="sequence mapped (its first --split frames, or all with --then)")
    p.add_argument("--split", type=int, default=0, help="frames mapped; the rest is run from the map")
    p.add_argument("--then", help="another sequence of the same place, run from the map of the whole --dataset")
    p.add_argument("--localize", action="store_true", help="the second run tracks only (sgslam run --localize)")
    p.add_argument("--sgslam", default=os.path.join(HERE, "..", "build", "sgslam"))
    p.add_argument("--config", default="tum_fr1")
    p.add_argument("--work", help="folder for the runs (default: a temporary one)")
    a = p.parse_args(argv)
    if bool(a.split) == bool(a.then):
        sys.exit("error: give --split N or --then SEQ")
    work = a.work or tempfile.mkdtemp(prefix="sgslam-map-reuse-")
    os.makedirs(work, exist_ok=True)
    src = os.path.abspath(a.dataset)
    if a.split:
        total = frame_count(src)
        if not 0 < a.split < total:
            sys.exit(f"error: --split must be within 1..{total - 1}")
        first, second = os.path.join(work, "mapped"), os.path.join(work, "rest")
        run([sys.executable, os.path.join(HERE, "kidnap.py"), src, first, "--drop", str(a.split), str(total - 1)])
        run([sys.executable, os.path.join(HERE, "kidnap.py"), src, second, "--drop", "0", str(a.split - 1)])
    else:
        first, second = src, os.path.abspath(a.then)
    map_file = os.path.join(work, "scene.map")
    common = ["--config", a.config, *extra]
    out1, out2 = os.path.join(work, "out-map"), os.path.join(work, "out-reuse")
    run([a.sgslam, "-q", "run", "--dataset", first, "--out", out1, "--save-map", map_file, *common])
    second_run = [a.sgslam, "run", "--dataset", second, "--out", out2, "--load-map", map_file, *common]
    if a.localize:
        second_run.append("--localize")
    log = run(second_run)
    info = run([a.sgslam, "map", "info", map_file])
    ev = json.loads(run([a.sgslam, "-q", "eval", "--gt", os.path.join(second, "groundtruth.txt"), "--est",
                         os.path.join(out2, "trajectory.txt"), "--align-with", os.path.join(out1, "trajectory.txt"),
                         "--json"]))
    with open(os.path.join(out2, "frames.csv"), encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(out1, "stats.json"), encoding="utf-8") as f:
        s1 = json.load(f)
    with open(os.path.join(out2, "stats.json"), encoding="utf-8") as f:
        s2 = json.load(f)
    localised = sum(r["state"] == "ok" for r in rows)
    first_ok = next((i for i, r in enumerate(rows) if r["state"] == "ok"), None)
    print(f"map: {s1['frames']} frames, {s1['keyframes']} keyframes; {info.splitlines()[0]}")
    print(f"reuse ({'localize' if a.localize else 'extend'}): {localised}/{len(rows)} frames localised "
          f"({100.0 * localised / max(1, len(rows)):.1f} %), first at frame {first_ok}; "
          f"keyframes {s1['keyframes']} -> {s2['keyframes']}")
    print(f"ATE of the localised frames in the map's frame: {ev['ate']['rmse']:.4f} m over {ev['ate']['pairs']} poses")
    for line in log.splitlines():
        if "loaded" in line:
            print(line.strip())
    print(f"runs in {work}")


if __name__ == "__main__":
    main()
