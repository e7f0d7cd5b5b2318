#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the default demo scene,
# writing a frame-time profile (and, once the renderer lands, a video) under out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
bash tools/build.sh
mkdir -p out
./build/sinew run assets/scenes/default.json --stats out/default_stats.json "$@"
echo "frame-time profile: out/default_stats.json"
