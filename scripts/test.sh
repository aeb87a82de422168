#!/usr/bin/env bash
# The test command: install what is missing, build, run the whole suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
echo "== tests"
ctest --preset default
