#!/usr/bin/env bash
# The test command: install what is missing, build, run the whole suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
echo "== tests"
log=build/ctest.log
ctest --preset default 2>&1 | tee "$log"
# Every test's data is in the repository, so nothing may skip for a missing file, tool or context;
# only the tests of an instruction set this CPU lacks may (they say so).
skipped=$(sed -n '/The following tests did not run:/,$p' "$log" | grep -E '\(Skipped\)' | grep -vE 'SampleRange\.TheKernel' || true)
if [[ -n "$skipped" ]]; then
    echo "error: tests skipped (a clone must run every test):" >&2
    echo "$skipped" >&2
    exit 1
fi
echo "== fuzzing every reader (bounded, fixed seed; scripts/fuzz.sh for longer runs)"
scripts/fuzz.sh --ci
