#!/usr/bin/env bash
# The test command: install what is missing, build, run the whole suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
echo "== tests"
ctest --preset default
echo "== fuzzing every reader (bounded, fixed seed; scripts/fuzz.sh for longer runs)"
scripts/fuzz.sh --ci
