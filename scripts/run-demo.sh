#!/usr/bin/env bash
# The main job: install what is missing, build, then compute the hidden-samples map of the
# built-in demo level (generated at build time into build/demo/) and print the result.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
echo "== sightline-cli shaft build/demo/demo.json"
build/app/sightline-cli info build/demo/demo.json | head -3
build/app/sightline-cli shaft build/demo/demo.json --mask build/demo/demo_mask.npy
