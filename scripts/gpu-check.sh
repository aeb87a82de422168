#!/usr/bin/env bash
# The GL paths on a real GPU, through EGL: the exact GL bitmask sampler against the CPU sampler and the
# ray-cast reference on the demo and the bench scenes (zero errors outside ties, times and ratios), and
# the paper's GL ambient occlusion against the exact CPU mode and a Monte-Carlo reference, and the
# many-light GL path (octahedral shadow maps) against the exact fast path. Writes its
# report to $OUT (default build/gpu-check) and exits non-zero when a GL answer is wrong or GL is absent.
#
#   scripts/gpu-check.sh [--quick] [BUILD_DIR]   (BUILD_DIR defaults to build; it must hold a built tree)
#
# Runs on llvmpipe too (Mesa's EGL), which is how it is tested where no GPU is lent (--quick: the demo
# and one bench scene at two sizes, one round, so that software GL finishes in minutes); the figures
# only mean something on a GPU.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
if [[ ${1:-} == --quick ]]; then quick=1; shift; fi
build=${1:-build}
out=${OUT:-$build/gpu-check}
cli=$build/app/sightline-cli
aobench=$build/app/sightline-ao-bench
for tool in "$cli" "$aobench"; do
    [[ -x $tool ]] || { echo "error: $tool is not built (scripts/setup.sh, or pass the build folder)" >&2; exit 1; }
done
mkdir -p "$out"
report=$out/report.txt
: > "$report"
say() { echo "$@" | tee -a "$report"; }

say "== GPU check, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores"
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee -a "$report" || true

# The demo and the bench scenes are generated, not stored: write them where the check can read them.
scenes=$out/scenes
"$cli" demo "$scenes" --seeds 1-1 > /dev/null
say "renderer: $("$cli" shaft "$scenes/demo.json" --method gl --gl-backend egl --json | sed -n 's/.*"strategy":"[^"]*(egl: \(.*\))".*/\1/p')"

say "== bitmask samplers: raycast (the exact reference), cpu, gl through EGL"
projects=("$scenes/demo.json" "$scenes/dense-mesh.json" "$scenes/few-occluders.json" "$scenes"/bench/*-1.json)
sizes=(--sources 32,128,1024 --receivers 32,128 --repeat 3)
aoRays=1024
if (( quick )); then
    projects=("$scenes/demo.json" "$scenes/bench/cluttered-rooms-1.json")
    sizes=(--sources 32,1024 --receivers 32 --repeat 1 --min-time 0)
    aoRays=64
fi
"$cli" bench "${projects[@]}" --methods embree-tuned,raycast,cpu,gl --gl-backend egl "${sizes[@]}" \
    --csv "$out/bench.csv" | tee -a "$report"

# Zero errors outside ties for the exact methods; gl against cpu, row by row.
awk -F, '
    NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
    {
        key = $col["project"] " " $col["source_samples"] " x " $col["receiver"]
        ms[key, $col["method"]] = $col["ms"]; keys[key] = 1
        if ($col["method"] ~ /^(raycast|cpu|gl)$/ && ($col["wrongly_blocked"] + $col["wrongly_free"]) > 0) {
            printf "error: %s %s: %d rays wrong outside ties\n", key, $col["method"], $col["wrongly_blocked"] + $col["wrongly_free"]
            bad = 1
        }
    }
    END {
        printf "%-60s %10s %10s %10s %12s %12s\n", "configuration", "cpu ms", "gl ms", "tuned ms", "gl/cpu", "tuned/gl"
        for (k in keys)
            if (ms[k, "gl"] > 0)
                printf "%-60s %10.2f %10.2f %10.2f %11.2fx %11.2fx\n", k, ms[k, "cpu"], ms[k, "gl"], ms[k, "embree-tuned"],
                       ms[k, "cpu"] / ms[k, "gl"], ms[k, "embree-tuned"] / ms[k, "gl"]
        exit bad
    }' "$out/bench.csv" | tee -a "$report"

say "== ambient occlusion: the GL mode (depth maps, the paper's way) through EGL, the bunny"
"$aobench" --gl-backend egl --mc "$aoRays" --repeat 1 | tee "$out/ao.txt" | tee -a "$report"
if grep -q '^gl: skipped' "$out/ao.txt"; then
    say "error: the GL ambient occlusion did not run"
    exit 1
fi
say "== many lights: octahedral shadow maps through EGL against the exact fast path, the demo's 300 light samples"
lightResolutions=(512 1024)
(( quick )) && lightResolutions=(256)
for resolution in "${lightResolutions[@]}"; do
    "$cli" lights "$scenes/demo_lights.json" --gl --gl-backend egl --gl-resolution "$resolution" --compare | tee -a "$report"
done
say "== done: $report"
