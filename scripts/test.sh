#!/usr/bin/env bash
# Sets up and builds when needed, then runs every test (GoogleTest through CTest).
# Tests that need ../shared data skip with a message when it is absent.
#   scripts/test.sh [extra ctest arguments, e.g. -R eval]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
ctest --test-dir build --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "$@"
