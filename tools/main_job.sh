#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the default demo scene (three
# creatures dropped on the ground: compliant, energy-limited, stiff), writing a video and a
# frame-time profile under out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
bash tools/build.sh
mkdir -p out
./build/sinew run assets/scenes/default.json --stats out/default_stats.json \
  --record out/default.mp4 --color-map energy "$@"
echo "video: out/default.mp4; frame-time profile: out/default_stats.json"
