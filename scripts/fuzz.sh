#!/usr/bin/env bash
# Builds the fuzz targets (fuzz/README.md) with clang-14, libFuzzer, ASan and UBSan
# in build-fuzz/, then runs each for N seconds, one after the other, on a working
# copy of its corpus, and prints a table. Exit status 1 when a target found something.
#   scripts/fuzz.sh [--seconds N] [target...]      (default: 600 s, every target)
# Working corpora: build-fuzz/corpus/<target>/ (seeded from fuzz/corpus/, kept
# between runs); findings: build-fuzz/artifacts/<target>/; logs: build-fuzz/logs/.
# Share the machine: nice -n 15 scripts/fuzz.sh; JOBS=2 builds with two jobs.
set -euo pipefail
cd "$(dirname "$0")/.."

ALL=(tum_lists trajectory detections config vocabulary map ply run_files)
# Bytes per input: a few times the largest seed, so the lists stay short enough
# that every input runs in milliseconds.
declare -A MAX_LEN=([tum_lists]=8192 [trajectory]=4096 [detections]=4096 [config]=16384 [vocabulary]=8192 [map]=16384
                    [ply]=4096 [run_files]=8192)

seconds=600
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds)
      [[ $# -gt 1 && $2 =~ ^[0-9]+$ && $2 -gt 0 ]] || { echo "fuzz.sh: --seconds needs a positive number" >&2; exit 2; }
      seconds=$2; shift 2 ;;
    -*) echo "fuzz.sh: unknown option '$1' (use --seconds N and target names: ${ALL[*]})" >&2; exit 2 ;;
    *)
      [ -n "${MAX_LEN[$1]:-}" ] || { echo "fuzz.sh: unknown target '$1' (targets: ${ALL[*]})" >&2; exit 2; }
      targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=("${ALL[@]}")
command -v clang++-14 >/dev/null || { echo "fuzz.sh: clang++-14 not found (scripts/setup.sh --fuzz --no-build installs it)" >&2; exit 1; }

out=build-fuzz
cmake -S . -B "$out" -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSGSLAM_FUZZ=ON \
  -DSGSLAM_BUILD_TESTS=OFF -DSGSLAM_BUILD_BENCH=OFF -DSGSLAM_ROS=OFF >/dev/null
cmake --build "$out" -j "${JOBS:-1}" --target "${targets[@]/%/_fuzz}"

rows=()
found=0
for t in "${targets[@]}"; do
  corpus=$out/corpus/$t artifacts=$out/artifacts/$t log=$out/logs/$t.log
  mkdir -p "$corpus" "$artifacts" "$out/logs"
  cp -n fuzz/corpus/"$t"/* "$corpus"/
  before=$(find "$artifacts" -type f | wc -l)
  echo "fuzz: $t for $seconds s (log $log)"
  start=$(date +%s)
  set +e
  "$out/fuzz/${t}_fuzz" -max_total_time="$seconds" -max_len="${MAX_LEN[$t]}" -rss_limit_mb=2048 -timeout=10 \
    -artifact_prefix="$artifacts/" -print_final_stats=1 "$corpus" >"$log" 2>&1
  status=$?
  set -e
  elapsed=$(( $(date +%s) - start ))
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  findings=$(( $(find "$artifacts" -type f | wc -l) - before ))
  [ "$status" = 0 ] || [ "$findings" -gt 0 ] || findings="exit $status"
  [ "$findings" = 0 ] || found=1
  rows+=("| $t | $elapsed | ${execs:-?} | $(( ${execs:-0} / (elapsed > 0 ? elapsed : 1) )) | $(find "$corpus" -type f | wc -l) | $findings |")
done

echo
echo "| target | seconds | executions | exec/s | corpus files | findings |"
echo "|---|---|---|---|---|---|"
printf '%s\n' "${rows[@]}"
[ "$found" = 0 ] || echo "findings: $out/artifacts/ (reproduce: $out/fuzz/<target>_fuzz FILE)"
exit "$found"
