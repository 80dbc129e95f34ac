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
echo "== HRPP on against off (tools/hrpp_bench.py: same binary, seed and image, off/on"
echo "   interleaved; ratios of device time per ray class and frame, < 1: HRPP faster)"
/usr/bin/python3 tools/hrpp_bench.py --scenes builtin:cornell --size 256x256 --spp 8 --repeat 1 \
  --images build/demo/default
/usr/bin/python3 tools/hrpp_bench.py --scenes builtin:cornell --size 256x256 --spp 8 --repeat 1 \
  --flags "--hrpp-mode exact" --images build/demo/exact
oiiotool build/demo/default/builtin_cornell_off0.exr build/demo/exact/builtin_cornell_on0.exr \
  build/demo/default/builtin_cornell_on0.exr --mosaic 3x1 --colorconvert linear sRGB \
  -o build/demo/hrpp_off_exact_speculative.png
echo "(HRPP off | exact | speculative (the default), side by side:"
echo " build/demo/hrpp_off_exact_speculative.png; exact renders HRPP off's image bit for bit)"
