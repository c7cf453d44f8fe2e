#!/usr/bin/env bash
# The paper's ablation (Table VI): runs `sgslam run` once per --mode on one sequence
# and prints a Markdown table of ATE (RMSE, mean, median, std), the rejection
# against ground-truth masks when the sequence has them, and the speed.
#   scripts/ablation.sh DATASET [OUT_DIR] [extra `sgslam run` options, e.g. --sequential]
# The detector model is found as `sgslam run` finds it (--model, detector.model_dir,
# $SGSLAM_MODEL_DIR, else the models shipped with sgslam).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ]; then
  echo "usage: scripts/ablation.sh DATASET [OUT_DIR] [sgslam run options]" >&2
  exit 2
fi
dataset=$1
out=${2:-sgslam-out/ablation-$(basename "$dataset")}
shift $(( $# >= 2 ? 2 : 1 ))
command -v python3 >/dev/null || { echo "ablation.sh: needs python3 (scripts/setup.sh installs it)" >&2; exit 1; }
[ -x build/sgslam ] || scripts/setup.sh
[ -f "$dataset/groundtruth.txt" ] || { echo "ablation.sh: $dataset/groundtruth.txt is missing: no ATE possible" >&2; exit 1; }

for mode in none semantic geometric sg; do
  echo "ablation: --mode $mode" >&2
  build/sgslam -q run --dataset "$dataset" --out "$out/$mode" --mode "$mode" "$@" >&2
  build/sgslam eval --gt "$dataset/groundtruth.txt" --est "$out/$mode/trajectory.txt" --json > "$out/$mode/eval.json"
done

python3 - "$out" <<'EOF'
import json, sys, os
out = sys.argv[1]
print("| mode | ATE RMSE [m] | mean | median | std | moving keypoints rejected | static keypoints lost | tracked | median ms/frame | fps |")
print("|---|---|---|---|---|---|---|---|---|---|")
for mode in ["none", "semantic", "geometric", "sg"]:
    ate = json.load(open(os.path.join(out, mode, "eval.json")))["ate"]
    st = json.load(open(os.path.join(out, mode, "stats.json")))
    truth = st.get("dynamic", {}).get("truth")
    rec = f"{100 * truth['recall']:.1f} %" if truth else "-"
    loss = f"{100 * truth['static_loss']:.1f} %" if truth else "-"
    print(f"| {mode} | {ate['rmse']:.4f} | {ate['mean']:.4f} | {ate['median']:.4f} | {ate['std']:.4f} | {rec} | {loss} "
          f"| {st['tracked']}/{st['frames']} | {st['median_ms']['frame']:.1f} | {st['fps']:.1f} |")
EOF
