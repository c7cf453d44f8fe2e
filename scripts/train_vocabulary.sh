#!/usr/bin/env bash
# Trains the vocabulary shipped in vocabulary/ again, deterministically: the ORB
# features of every third frame of six synthetic sequences (made here by
# `sgslam synth` with fixed seeds) and of every second frame of the real TUM RGB-D
# freiburg1_rpy sequence (CC BY 4.0, Sturm et al. 2012); k 10, L 5, seed 1.
# vocabulary/README.md says why, and how well it retrieves.
#   scripts/train_vocabulary.sh [TUM_FR1_RPY_DIR] [OUT_FILE]
set -euo pipefail
cd "$(dirname "$0")/.."
rpy="$(realpath "${1:-${SGSLAM_SHARED_DIR:-../shared}/data/tum_fr1_rpy}")"
out="${2:-vocabulary/orb-k10-l5.vocab}"
[ -f "$rpy/rgb.txt" ] || { echo "error: no TUM fr1_rpy sequence at $rpy (pass its folder)" >&2; exit 1; }
[ -x build/sgslam ] || scripts/setup.sh --target sgslam
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# Every n-th image of a TUM-layout folder, as absolute paths.
every() { grep -v '^#' "$1/rgb.txt" | awk -v n="$2" -v d="$1" '(NR - 1) % n == 0 { print d "/" $2 }'; }
for spec in "static 11" "static 12" "static 13" "objects 11" "rpy 14" "walkers 15"; do
  set -- $spec
  build/sgslam -q synth --out "$work/$1$2" --preset "$1" --seed "$2" --frames 300
  every "$work/$1$2" 3 >> "$work/images.txt"
done
every "$rpy" 2 >> "$work/images.txt"
build/sgslam vocab train --images "$work/images.txt" --k 10 --levels 5 --seed 1 --out "$out"
build/sgslam vocab info "$out"
