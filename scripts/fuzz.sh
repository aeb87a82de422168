#!/usr/bin/env bash
# Builds the libFuzzer harnesses (preset `fuzz`: clang, ASan, UBSan) and runs each, seeded with
# tests/fuzz/corpus/<reader>/.
#   scripts/fuzz.sh [SECONDS_EACH] [READER...]   a timed run (default 30 s each, every reader),
#                                                 keeping what it learns in build-fuzz/corpus/
#   scripts/fuzz.sh --ci [READER...]              what CI runs: a fixed seed and a fixed number of
#                                                 inputs per reader (so a run repeats exactly), from
#                                                 the committed seeds only
# Prints one line per reader: executions, coverage, findings.
# A finding (crash, sanitizer report, leak, timeout over 10 s, more than 2 GB) fails the script;
# its reproducer is left in build-fuzz/findings/<reader>/.
set -euo pipefail
cd "$(dirname "$0")/.."
ci=0
seconds=30
if [ "${1:-}" = "--ci" ]; then ci=1; shift
elif [ -n "${1:-}" ] && [[ "$1" =~ ^[0-9]+$ ]]; then seconds="$1"; shift; fi
readers=("$@")
[ ${#readers[@]} -gt 0 ] || readers=(gltf glb obj ply off stl map project npy image pvs bsp)

cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)" >/dev/null

status=0
for reader in "${readers[@]}"; do
  work="build-fuzz/corpus/$reader"
  findings="build-fuzz/findings/$reader"
  if [ $ci -eq 1 ]; then
    # About 30 s a reader on a 2-core CI machine; max_total_time only guards against a slow machine.
    case "$reader" in image) runs=10000 ;; *) runs=100000 ;; esac   # image decoding is slow
    bound=(-seed=1 -runs="${SIGHTLINE_FUZZ_RUNS:-$runs}" -max_total_time=120)
    work="build-fuzz/ci-corpus/$reader"
    rm -rf "$work"
  else
    bound=(-max_total_time="$seconds")
  fi
  mkdir -p "$work" "$findings"
  log="build-fuzz/fuzz-$reader.log"
  set +e
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "build-fuzz/tests/fuzz/fuzz_$reader" "${bound[@]}" -timeout=10 -rss_limit_mb=2048 \
    -malloc_limit_mb=2048 -artifact_prefix="$findings/" -print_final_stats=1 \
    "$work" "tests/fuzz/corpus/$reader" >"$log" 2>&1
  rc=$?
  set -e
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || true)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || true)
  if [ $rc -eq 0 ]; then
    printf '%-8s %10s runs  %6s edges  %6s features  no findings\n' "$reader" "${runs:-?}" "${cov:-?}" "${ft:-?}"
  else
    printf '%-8s FINDING (exit %d): see %s and %s\n' "$reader" "$rc" "$log" "$findings"
    grep -m3 -E 'ERROR|SUMMARY|runtime error' "$log" || true
    status=1
  fi
done
exit $status
