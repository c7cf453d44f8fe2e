#!/usr/bin/env bash
# Sets up and builds when needed, then runs the tests (GoogleTest through CTest):
# the fast set, every test but those labelled `slow` (ctest -LE slow: the
# whole-system suites and the browser, ROS and fault-suite end-to-end tests), or
# with --all every test. Tests that need ../shared data skip with a message when
# it is absent.
#   scripts/test.sh [--all] [extra ctest arguments, e.g. -R eval]
set -euo pipefail
cd "$(dirname "$0")/.."
select=(-LE slow)
args=()
for arg in "$@"; do
  if [ "$arg" = --all ]; then select=(); else args+=("$arg"); fi
done
scripts/setup.sh
ctest --test-dir build --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "${select[@]}" "${args[@]}"
