#!/usr/bin/env bash
# Set up, build and run hrpp's main job on the built-in default scene, printing what it found.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
tools/build.sh release
hrpp=build/release/host/hrpp
echo
echo "== $hrpp scene   (the default scene: builtin:cornell)"
"$hrpp" scene
echo
echo "== $hrpp render   (builtin:cornell, 256x256, 8 spp: per-kernel device time and counters)"
mkdir -p build/demo
"$hrpp" render --out build/demo/cornell.png --stats build/demo/cornell.json
echo "(image: build/demo/cornell.png, linear EXR with --out FILE.exr; stats: build/demo/cornell.json)"
echo
echo "== $hrpp bench --hrpp on   (HRPP off vs on, side by side: gpu and gpu-hrpp rows)"
"$hrpp" bench --rays 65536 --no-embree --repeat 1 --hrpp on --hrpp-mode exact --kinds primary,ao
