#!/usr/bin/env bash
# Checksums of what sequential runs write, for refactors that must not change the
# behaviour: every mode on every dataset given, `--sequential` (the same bytes on
# every run), one line per run and output file.
#   scripts/checksums.sh [--sgslam BIN] [--modes "none semantic geometric sg"] DATASET...
#   scripts/checksums.sh ../shared/data/dyn_dev ../shared/data/tum_fr1_rpy > before.txt
# then the same after the change, and `diff before.txt after.txt`.
set -euo pipefail
cd "$(dirname "$0")/.."

bin=build/sgslam
modes="none semantic geometric sg"
datasets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --sgslam) bin=$2; shift 2 ;;
    --modes) modes=$2; shift 2 ;;
    -*) echo "checksums.sh: unknown option '$1'" >&2; exit 2 ;;
    *) datasets+=("$1"); shift ;;
  esac
done
[ ${#datasets[@]} -gt 0 ] || { echo "usage: scripts/checksums.sh [--sgslam BIN] [--modes M] DATASET..." >&2; exit 2; }
[ -x "$bin" ] || { echo "checksums.sh: no program at '$bin' (build it first)" >&2; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/sgslam-checksums.XXXXXX")
trap 'rm -rf "$work"' EXIT
for dataset in "${datasets[@]}"; do
  name=$(basename "$dataset")
  for mode in $modes; do
    out="$work/$name-$mode"
    "$bin" -q run --dataset "$dataset" --mode "$mode" --sequential --out "$out" >/dev/null
    # Outputs that depend on the run alone (not on its timing or the machine).
    for f in trajectory.txt keyframes.txt detections.txt objects.json cloud.ply; do
      [ -f "$out/$f" ] && echo "$name $mode $f $(sha256sum < "$out/$f" | cut -c1-16)"
    done
  done
done
