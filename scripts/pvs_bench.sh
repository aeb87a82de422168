#!/bin/sh
# PVS bake benchmark (docs/pvs.md): the demo level (255 cells x 175 objects) and the
# generated level (4,096 cells x 2,000 objects), each baked and checked against the dense
# reference in one run, in the default and the safe mode; prints the load average, one JSON
# summary per run (time, passes, miss rates, sizes) and the process's CPU time.
#   scripts/pvs_bench.sh [BUILD_DIR] [OUT_DIR]
set -eu
BUILD=${1:-build}
OUT=${2:-/tmp/sightline-pvs-bench}
CLI="$BUILD/app/sightline-cli"
mkdir -p "$OUT"
"$CLI" demo "$OUT/demo" > /dev/null
"$CLI" pvs level "$OUT/level" --force > /dev/null
run() {
  echo "$1 ${2:-default}: $(uptime)"
  /usr/bin/time -f "cpu %U s user, %S s system, %e s wall" \
    "$CLI" pvs bake "$3" --out "$OUT/$1.pvs" --check --gaps "$OUT/$1${2:+_safe}_gaps.json" --print-json ${2:-}
}
for mode in "" "--safe"; do
  run demo "$mode" "$OUT/demo/demo.json"
done
for mode in "" "--safe"; do
  run level "$mode" "$OUT/level/pvs_level.json"
done
