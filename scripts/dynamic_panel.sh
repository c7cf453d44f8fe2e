#!/usr/bin/env bash
# The development panel of dynamic sequences (scripts/dynamic_panel.py): composites of
# tum_fr1_rpy and generated presets, each run sequentially, one table.
exec python3 "$(dirname "$0")/dynamic_panel.py" "$@"
