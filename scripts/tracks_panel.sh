#!/usr/bin/env bash
# The mover tracks against the true movers (docs/movers.md): `sgslam run --sequential`
# on `dyn_dev` and on generated `walkers` sequences (seeds 1-3), then one table of
# stats.json's tracks.truth (coverage of movers over 10 % of the image, id switches,
# false confirmed tracks, median centroid error), the ATE and the rejection's truth.
#   scripts/tracks_panel.sh OUT_DIR [CONFIG.yaml] [extra `sgslam run` options]
# Environment: SGSLAM_BIN another binary (default build/sgslam); DYN_DEV the dyn_dev
# folder (default ../shared/data/dyn_dev; skipped when absent); SEEDS the walkers
# seeds (default "1 2 3"). The walkers sequences are rendered once into OUT_DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ]; then
  echo "usage: scripts/tracks_panel.sh OUT_DIR [CONFIG.yaml] [sgslam run options]" >&2
  exit 2
fi
out=$1
shift
config=()
if [ $# -ge 1 ] && [[ "$1" != -* ]]; then
  [ -f "$1" ] || { echo "tracks_panel.sh: config $1 not found" >&2; exit 1; }
  config=(--config "$1")
  shift
fi
command -v python3 >/dev/null || { echo "tracks_panel.sh: needs python3 (scripts/setup.sh installs it)" >&2; exit 1; }
bin=${SGSLAM_BIN:-build/sgslam}
[ -n "${SGSLAM_BIN:-}" ] || [ -x build/sgslam ] || scripts/setup.sh
[ -x "$bin" ] || { echo "tracks_panel.sh: $bin is not an executable" >&2; exit 1; }
mkdir -p "$out"

runs=()
dyn_dev=${DYN_DEV:-../shared/data/dyn_dev}
if [ -f "$dyn_dev/dynamic_objects.txt" ]; then
  echo "tracks_panel: dyn_dev" >&2
  "$bin" -q run --dataset "$dyn_dev" --out "$out/run_dyn_dev" --sequential "${config[@]}" "$@" >&2
  runs+=(dyn_dev)
else
  echo "tracks_panel: no $dyn_dev/dynamic_objects.txt: dyn_dev skipped" >&2
fi
for seed in ${SEEDS:-1 2 3}; do
  seq="$out/walkers_$seed"
  [ -f "$seq/movers.txt" ] || "$bin" -q synth --preset walkers --seed "$seed" --out "$seq" --force >&2
  echo "tracks_panel: walkers seed $seed" >&2
  "$bin" -q run --dataset "$seq" --out "$out/run_walkers_$seed" --sequential "${config[@]}" "$@" >&2
  runs+=("walkers_$seed")
done

python3 - "$out" "${runs[@]}" <<'PY'
import json, os, sys
out, runs = sys.argv[1], sys.argv[2:]
print("| sequence | coverage (worst mover) | id switches (worst) | false tracks /100 frames | centroid error m | ATE m | moving rejected | static lost | tracker ms |")
print("|---|---|---|---|---|---|---|---|---|")
for name in runs:
    st = json.load(open(os.path.join(out, "run_" + name, "stats.json")))
    tr = st.get("tracks", {})
    t = tr.get("truth")
    d = st.get("dynamic", {}).get("truth", {})
    ate = st.get("ate", {}).get("rmse")
    if t is None:
        print(f"| {name} | no truth | | | | | | | |")
        continue
    print(f"| {name} | {t['coverage']:.3f} ({t['min_coverage']:.3f}) | {t['max_id_switches']} | "
          f"{t['false_per_100_frames']:.1f} ({t['false_tracks']}) | {t['median_centroid_error_m']:.3f} | "
          f"{ate:.4f} | {d.get('recall', 0):.3f} | {d.get('static_loss', 0):.3f} | {tr.get('median_ms', 0):.2f} |")
PY
