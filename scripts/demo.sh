#!/usr/bin/env bash
# Sets up and builds the program alone (not the tests) when needed, then runs
# `sgslam demo`: a generated dynamic sequence, processed and evaluated. Extra
# arguments go to `sgslam demo`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --target sgslam
build/sgslam demo "$@"
