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
