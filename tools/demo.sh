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
echo
echo "== $hrpp render --hrpp on   (HRPP off | exact | speculative, side by side, same seed)"
"$hrpp" render --hrpp on --hrpp-mode exact --hrpp-count --out build/demo/cornell_exact.png \
  --stats build/demo/cornell_exact.json | grep -E '^(kernel +trace|hrpp)|savings'
"$hrpp" render --hrpp on --hrpp-mode speculative --hrpp-count --out build/demo/cornell_spec.png \
  --stats build/demo/cornell_spec.json | grep -E '^(kernel +trace|hrpp)|savings'
oiiotool build/demo/cornell.png build/demo/cornell_exact.png build/demo/cornell_spec.png \
  --mosaic 3x1 -o build/demo/hrpp_off_exact_speculative.png
echo "exact vs off:       $(idiff build/demo/cornell.png build/demo/cornell_exact.png | tail -1)"
echo "speculative vs off: $(idiff build/demo/cornell.png build/demo/cornell_spec.png | tail -1 || true)"
echo "(side by side: build/demo/hrpp_off_exact_speculative.png)"
