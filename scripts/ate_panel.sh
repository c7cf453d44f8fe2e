#!/usr/bin/env bash
# ATE of one setting over a panel of nearby runs: `sgslam run --sequential` once per
# ORB feature budget (default 900 950 1000 1050 1100), then the median, min and max.
# Why: on fr1_rpy-based sequences the ATE of one deterministic run swings by 2x
# with any small change (dyn_dev sg: 0.093-0.158 m over the five budgets), so one
# run cannot tell a better setting from a lucky one. Compare settings by their
# panel medians, run on the same machine.
#   scripts/ate_panel.sh DATASET OUT_DIR [CONFIG.yaml] [extra `sgslam run` options]
# CONFIG.yaml may set anything but orb.features (the panel sets that).
# Environment: FEATURES="..." replaces the budgets; SGSLAM_BIN another binary
# (default build/sgslam), e.g. a copy kept while the tree is rebuilt.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ]; then
  echo "usage: scripts/ate_panel.sh DATASET OUT_DIR [CONFIG.yaml] [sgslam run options]" >&2
  exit 2
fi
dataset=$1
out=$2
shift 2
base=""
if [ $# -ge 1 ] && [ -z "$1" ]; then
  shift  # an empty CONFIG argument: none
elif [ $# -ge 1 ] && [[ "$1" != -* ]]; then
  base=$1
  shift
  [ -f "$base" ] || { echo "ate_panel.sh: config $base not found" >&2; exit 1; }
  if grep -q '^orb:' "$base"; then
    echo "ate_panel.sh: $base has an orb: section; the panel sets orb.features itself" >&2
    exit 1
  fi
fi
command -v python3 >/dev/null || { echo "ate_panel.sh: needs python3 (scripts/setup.sh installs it)" >&2; exit 1; }
bin=${SGSLAM_BIN:-build/sgslam}
[ -n "${SGSLAM_BIN:-}" ] || [ -x build/sgslam ] || scripts/setup.sh
[ -x "$bin" ] || { echo "ate_panel.sh: $bin is not an executable" >&2; exit 1; }
[ -f "$dataset/groundtruth.txt" ] || { echo "ate_panel.sh: $dataset/groundtruth.txt is missing: no ATE" >&2; exit 1; }
mkdir -p "$out"

features=${FEATURES:-900 950 1000 1050 1100}
for n in $features; do
  cfg="$out/config_$n.yaml"
  { [ -n "$base" ] && cat "$base" && echo; printf 'orb:\n  features: %s\n' "$n"; } > "$cfg"
  echo "ate_panel: orb.features $n" >&2
  "$bin" -q run --dataset "$dataset" --out "$out/f$n" --config "$cfg" --sequential "$@" >&2
done

python3 - "$out" $features <<'EOF'
import json, os, statistics, sys
out, budgets = sys.argv[1], sys.argv[2:]
rows = []
print("| orb.features | ATE RMSE [m] | tracked | keyframes |")
print("|---|---|---|---|")
for n in budgets:
    st = json.load(open(os.path.join(out, "f" + n, "stats.json")))
    ate = st.get("ate", {}).get("rmse")
    rows.append(ate)
    a = f"{ate:.4f}" if ate is not None else "-"
    print(f"| {n} | {a} | {st['tracked']}/{st['frames']} | {st.get('keyframes', '-')} |")
v = [r for r in rows if r is not None]
if v:
    print(f"\nATE RMSE over {len(v)} runs: median {statistics.median(v):.4f} m, min {min(v):.4f}, max {max(v):.4f}")
EOF
