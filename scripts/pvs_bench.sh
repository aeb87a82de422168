#!/bin/sh
# PVS bake benchmark (issue 17, docs/pvs.md): the demo level (255 cells x 175 objects) and the
# generated level (4,096 cells x 2,000 objects), each baked and checked against the dense
# reference in one run; prints one JSON summary per level (time, miss rates, sizes).
#   scripts/pvs_bench.sh [BUILD_DIR] [OUT_DIR]
set -eu
BUILD=${1:-build}
OUT=${2:-/tmp/sightline-pvs-bench}
CLI="$BUILD/app/sightline-cli"
mkdir -p "$OUT"
"$CLI" demo "$OUT/demo" > /dev/null
"$CLI" pvs level "$OUT/level" > /dev/null
for mode in "" "--safe"; do
  echo "demo ${mode:-default}:"
  "$CLI" pvs bake "$OUT/demo/demo.json" --out "$OUT/demo.pvs" --check --gaps "$OUT/demo_gaps.json" --print-json $mode
done
echo "generated level:"
"$CLI" pvs bake "$OUT/level/pvs_level.json" --out "$OUT/level.pvs" --check --gaps "$OUT/level_gaps.json" --print-json
