#!/usr/bin/env bash
# The main job: install what is missing, build, then on the built-in demo level (generated at
# build time into build/demo/):
#   - with a display: open the editor on the demo project;
#   - without one: compute the hidden-samples map with the CLI, print the result, render the
#     project's view to build/demo/demo.png (OSMesa, no display needed), and write the receiver's
#     importance map over the demo's animation (build/demo/importance.png, .npy).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ] && [ -z "${SIGHTLINE_HEADLESS:-}" ]; then
  echo "== sightline build/demo/demo.json (the editor)"
  exec build/app/sightline build/demo/demo.json
fi
echo "== sightline-cli shaft build/demo/demo.json"
build/app/sightline-cli info build/demo/demo.json | head -3
build/app/sightline-cli shaft build/demo/demo.json --mask build/demo/demo_mask.npy
echo "== sightline --screenshot build/demo/demo.png build/demo/demo.json"
build/app/sightline --screenshot build/demo/demo.png build/demo/demo.json
echo "== sightline-cli importance build/demo/demo.json --out build/demo/importance.png"
build/app/sightline-cli importance build/demo/demo.json --out build/demo/importance.png --npy build/demo/importance.npy
