#!/usr/bin/env bash
# The speed benchmark (scripts/speed.py): modes alternated on the same sequences, medians.
exec python3 "$(dirname "$0")/speed.py" "$@"
