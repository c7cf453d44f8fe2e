#!/usr/bin/env bash
# The sanitizer jobs of CI (.ci/run), also for use by hand:
#   scripts/sanitize.sh [--asan] [--tsan] [--all]     (both jobs when neither is given)
# --asan: AddressSanitizer + UBSan build in build-asan/; the unit tests (every test
#   but the whole-system suites, which run the full pipeline on rendered sequences
#   for 30-170 s each under ASan: 26 minutes of the 32 of every test; --all runs
#   them too), then one short end-to-end run: a synthetic `walkers` sequence through
#   `sgslam run` in parallel mode with the real detector and --save-map.
# --tsan: ThreadSanitizer build of the program and the threaded end-to-end test in
#   build-tsan/; that test's parallel run and the same end-to-end run, the viewer's
#   server tests and a `run --viewer` watched by a headless chromium page, a
#   `run --foxglove` with its clients and a `run --mcap` cut by Ctrl-C; with ROS 1
#   installed, the ROS node on a synthetic sequence through a private master.
# A report from either sanitizer fails the job (exit status 1).
set -euo pipefail
cd "$(dirname "$0")/.."

asan=0 tsan=0 all=0
for arg in "$@"; do
  case "$arg" in
    --asan) asan=1 ;;
    --tsan) tsan=1 ;;
    --all) all=1 ;;
    *) echo "sanitize.sh: unknown option '$arg' (use --asan, --tsan, --all)" >&2; exit 2 ;;
  esac
done
[ $asan = 1 ] || [ $tsan = 1 ] || { asan=1; tsan=1; }

work=$(mktemp -d "${TMPDIR:-/tmp}/sgslam-sanitize.XXXXXX")
trap 'rm -rf "$work"' EXIT
jobs=$(nproc 2>/dev/null || echo 2)

# Renders a short walkers sequence with $1/sgslam and runs it in parallel mode.
end_to_end() {
  local bin=$1/sgslam name=$2
  "$bin" -q synth --preset walkers --frames 60 --out "$work/$name-seq"
  "$bin" -q run --dataset "$work/$name-seq" --out "$work/$name-out" --save-map "$work/$name.map"
  "$bin" -q map info "$work/$name.map" >/dev/null
  echo "sanitize: $name end-to-end run clean"
}

# The whole-system test files (tests/<module>/<name>_test.cpp -> test_<module>_<name>)
# and their suites.
SYSTEM_FILES='system/(slam_synthetic|localisation|loop_closing|relocalisation|map_reuse|snapshot)|semantic/semantic_system|synth/walkers'
SYSTEM_SUITES='SlamSynthetic|Localisation|LocalisationSynthetic|LoopClosing|Relocalisation|MapReuse|Snapshots|SemanticSystem|SynthWalkers'

if [ $asan = 1 ]; then
  if [ $all = 1 ]; then
    scripts/setup.sh --asan
    skip='^$'
  else
    targets=(--target sgslam)
    for f in fuzz/*_fuzz.cpp; do targets+=(--target "$(basename "${f%.cpp}")"); done  # Fuzz.<name> replays
    for f in $(cd tests && find . -name '*_test.cpp' | sed 's|^\./||' | grep -Ev "^($SYSTEM_FILES)_test\.cpp$" | sort); do
      targets+=(--target "test_$(echo "${f%_test.cpp}" | tr / _)")
    done
    scripts/setup.sh --asan "${targets[@]}"
    skip="^($SYSTEM_SUITES)\\.|_NOT_BUILT"
  fi
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  ctest --test-dir build-asan --output-on-failure -j "$jobs" -E "$skip"
  end_to_end build-asan asan
fi

if [ $tsan = 1 ]; then
  ros_targets=()
  if command -v rosmaster >/dev/null && pkg-config --exists roscpp 2>/dev/null; then
    ros_targets=(--target sgslam_ros --target sgslam_ros_play)
  fi
  scripts/setup.sh --tsan --target sgslam --target test_system_slam_synthetic --target test_viewer_server "${ros_targets[@]}"
  export TSAN_OPTIONS="suppressions=$PWD/tests/sanitizers/tsan.supp halt_on_error=1 second_deadlock_stack=1"
  build-tsan/tests/test_system_slam_synthetic --gtest_filter='*Parallel*'
  end_to_end build-tsan tsan
  # The viewer's server thread against the run's threads: its own tests, and a run
  # watched by a real page (skipped, 77, without chromium).
  build-tsan/tests/test_viewer_server
  status=0
  node viewer/tests/browser_test.mjs --sgslam build-tsan/sgslam --work "$work/tsan-viewer" --parallel 1 || status=$?
  [ $status = 0 ] || [ $status = 77 ] || exit $status
  echo "sanitize: tsan viewer run clean"
  # The Foxglove server's and the MCAP recorder's threads: a live run with a client
  # subscribed to every channel and one that never reads, and a recorded run cut by
  # Ctrl-C (skipped, 77, without the npm packages).
  for t in foxglove_live foxglove_mcap; do
    status=0
    node viewer/tests/${t}_test.mjs --sgslam build-tsan/sgslam --work "$work/tsan-$t" || status=$?
    [ $status = 0 ] || [ $status = 77 ] || exit $status
  done
  echo "sanitize: tsan Foxglove runs clean"
  # The ROS node's threads (its callbacks, the tracking thread, the system's) on a
  # synthetic sequence through a private master; a report ends the node or the
  # player (66) and fails the script. Slow under TSan, so only its outputs and
  # exit are checked (--measure-only). Debian's roscpp is not instrumented: its own
  # lock order and reference counts are suppressed (ros/tests/tsan_ros.supp).
  if [ ${#ros_targets[@]} -gt 0 ]; then
    cat tests/sanitizers/tsan.supp ros/tests/tsan_ros.supp > "$work/tsan_ros.supp"
    TSAN_OPTIONS="suppressions=$work/tsan_ros.supp halt_on_error=1 second_deadlock_stack=1" \
      /usr/bin/python3 ros/tests/ros_e2e.py --build build-tsan --frames 60 --rate 0.3 --now --measure-only
    echo "sanitize: tsan ROS node run clean"
  fi
fi
