#!/usr/bin/env python3
"""The development panel of dynamic sequences (issue #50): composites made from the
real tum_fr1_rpy with the shared generator (crowds close to the camera, a seated person
shifting, an unknown moving box, fast and slow walkers, a walker along the epipolar
direction) and generated presets (`walkers`, `objects`), each run once with
`sgslam run --sequential` (deterministic), then one Markdown table: ATE of the final and
of the online poses, frames lost, the rejection's truth, and the worst sequence.

  scripts/dynamic_panel.sh OUT_DIR [--only NAME,...] [--config FILE] [-- sgslam run options]

The sequences are rendered once into OUT_DIR/seq/NAME (kept: delete them to remake
them); the runs go to OUT_DIR/run/NAME. The composites need Debian's python3-numpy,
python3-opencv and python3-scipy (`scripts/setup.sh --panel`) and the generator
(`$SGSLAM_SHARED_DIR/tools/composite` or ../shared/tools/composite) with its source
sequence; without them only the presets run, with a message saying so.

The panel's composites are billboards (flat, rigid): a gain on them is necessary, not
sufficient."""
import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# name -> the generator's options (the source is tum_fr1_rpy; 300 frames = 10 s each)
COMPOSITES = {
    "crowd": "--seed 101 --people 3 --speed fast --path line,cross,circle --coverage high "
             "--person-sprites p_ball,p_walk,p_blue --count 300",
    "crowd_near": "--seed 107 --people 3 --speed medium --path cross,line,circle --dist 0.5,0.75 "
                  "--person-sprites p_walk,p_blue,p_ball --start 300 --count 300",
    "box": "--seed 102 --people 1 --object --start 150 --count 300",
    "seated": "--seed 103 --people 1 --person-sprites p_seat --speed 0.1 --path line --coverage medium "
              "--start 60 --count 300",
    "fast": "--seed 104 --people 2 --speed fast --path cross,line --coverage medium --start 300 --count 300",
    "slow": "--seed 105 --people 2 --speed slow --path circle,line --start 380 --count 300",
    "epipolar": "--seed 106 --people 1 --epipolar --start 200 --count 300",
}
PRESETS = ["walkers:1", "walkers:2", "walkers:3", "objects:1", "objects:2"]


def shared_dir():
    return os.environ.get("SGSLAM_SHARED_DIR") or os.path.join(ROOT, "..", "shared")


def make_composite(name, out, log):
    gen = os.path.join(shared_dir(), "tools", "composite", "gen_dynamic.py")
    src = os.path.join(shared_dir(), "data", "tum_fr1_rpy")
    if not os.path.isfile(gen) or not os.path.isdir(src):
        return f"no generator at {gen} or no {src}"
    probe = subprocess.run(["/usr/bin/python3", "-c", "import numpy, cv2, scipy"], capture_output=True)
    if probe.returncode != 0:
        return "the generator needs python3-numpy, python3-opencv and python3-scipy (scripts/setup.sh --panel)"
    cmd = ["/usr/bin/python3", gen, "--src", src, "--out", out] + shlex.split(COMPOSITES[name])
    with open(log, "w", encoding="utf-8") as f:
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.exit(f"dynamic_panel: {' '.join(cmd)} failed ({r.returncode}); see {log}")
    return None


def make_preset(sgslam, name, out):
    preset, _, seed = name.partition(":")
    r = subprocess.run([sgslam, "-q", "synth", "--preset", preset, "--seed", seed or "1", "--out", out, "--force"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"dynamic_panel: sgslam synth --preset {preset} failed ({r.returncode}):\n{r.stdout}{r.stderr}")


def ate_of(sgslam, gt, est):
    if not os.path.isfile(est) or os.path.getsize(est) == 0:
        return None
    r = subprocess.run([sgslam, "eval", "--gt", gt, "--est", est, "--json"], capture_output=True, text=True)
    if r.returncode != 0:
        return None
    return json.loads(r.stdout)["ate"]["rmse"]


def run(sgslam, seq, out, options):
    cmd = [sgslam, "-q", "run", "--dataset", seq, "--out", out, "--sequential"] + options
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"dynamic_panel: {' '.join(cmd)} failed ({r.returncode}):\n{r.stderr[-3000:]}")
    with open(os.path.join(out, "stats.json"), encoding="utf-8") as f:
        s = json.load(f)
    truth = s.get("dynamic", {}).get("truth", {})
    fallback = s.get("odometry", {}).get("frames")
    return {
        "frames": s.get("frames"),
        "lost": s.get("lost"),
        "fallback": fallback,
        "ate": s.get("ate", {}).get("rmse"),
        "online": ate_of(sgslam, os.path.join(seq, "groundtruth.txt"), os.path.join(out, "trajectory_online.txt")),
        "recall": truth.get("recall"),
        "static_loss": truth.get("static_loss"),
    }


def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--only", help="a comma list of the panel's names (default: all)")
    ap.add_argument("--config", help="a config file for every run")
    ap.add_argument("--sgslam", default=os.path.join(ROOT, "build", "sgslam"))
    ap.add_argument("--markdown", help="also write the table to this file")
    ap.add_argument("extra", nargs="*", help="after --: more sgslam run options (default --mode sg)")
    a = ap.parse_args()
    if not os.access(a.sgslam, os.X_OK):
        sys.exit(f"dynamic_panel: no sgslam binary at {a.sgslam} (build first, or --sgslam PATH)")
    names = list(COMPOSITES) + PRESETS
    if a.only:
        names = [n for n in a.only.split(",") if n]
        unknown = [n for n in names if n not in COMPOSITES and n not in PRESETS]
        if unknown:
            sys.exit(f"dynamic_panel: not in the panel: {', '.join(unknown)} (it has {', '.join(list(COMPOSITES) + PRESETS)})")
    options = (["--config", os.path.abspath(a.config)] if a.config else []) + (a.extra or ["--mode", "sg"])
    rows = []
    for name in names:
        seq = os.path.join(a.out, "seq", name.replace(":", "_"))
        if not os.path.isfile(os.path.join(seq, "rgb.txt")):
            os.makedirs(os.path.dirname(seq), exist_ok=True)
            print(f"dynamic_panel: making {name}", file=sys.stderr, flush=True)
            if name in COMPOSITES:
                why = make_composite(name, seq, seq + ".log")
                if why:
                    print(f"dynamic_panel: {name} skipped: {why}", file=sys.stderr)
                    continue
            else:
                make_preset(a.sgslam, name, seq)
        print(f"dynamic_panel: running {name}", file=sys.stderr, flush=True)
        r = run(a.sgslam, seq, os.path.join(a.out, "run", name.replace(":", "_")), options)
        rows.append((name, r))
    lines = ["| sequence | frames | lost | odometry | ATE m | online ATE m | moving rejected | static lost |",
             "|---|---|---|---|---|---|---|---|"]
    for name, r in rows:
        lines.append(f"| {name} | {r['frames']} | {r['lost']} | {fmt(r['fallback'], 'd')} | {fmt(r['ate'], '.4f')} | "
                     f"{fmt(r['online'], '.4f')} | {fmt(r['recall'], '.3f')} | {fmt(r['static_loss'], '.3f')} |")
    scored = [(r["ate"], name) for name, r in rows if r["ate"] is not None]
    comps = [r["ate"] for name, r in rows if name in COMPOSITES and r["ate"] is not None]
    how = " ".join(shlex.quote(x) for x in sys.argv[1:])
    note = f"\n`scripts/dynamic_panel.sh {how}`"
    if scored:
        worst = max(scored)
        note += f"; worst: {worst[1]} {worst[0]:.4f} m"
    if comps:
        note += f"; composites' median ATE {statistics.median(comps):.4f} m"
    note += f"; frames lost in all: {sum(r['lost'] or 0 for _, r in rows)}."
    table = "\n".join(lines) + "\n" + note
    print(table)
    if a.markdown:
        with open(a.markdown, "w", encoding="utf-8") as f:
            f.write(table + "\n")


if __name__ == "__main__":
    main()
