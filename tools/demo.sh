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
echo "(one run each: these Mrays/s and ratios show what runs, not which is faster; below, pairs)"
echo "(uptime: $(uptime | sed 's/^ *//'))"
echo
# Off/on pairs, interleaved: hrpp_bench.py's table takes the fastest of each side; the spread of
# the pairs' own ratios says whether the difference is more than the noise of this machine.
pairs=5
spread() {  # the frame's on/off device-time ratio of each pair in build/demo/$1
  /usr/bin/python3 - "build/demo/$1" "$pairs" <<'PY'
import json, statistics, sys
d, n = sys.argv[1], int(sys.argv[2])
ms = lambda f: json.load(open(f"{d}/builtin_cornell_{f}.json"))["kernels_ms_total"]
r = sorted(ms(f"on{i}") / ms(f"off{i}") for i in range(n))
verdict = ("the pairs disagree on which is faster: no difference measured" if r[0] < 1 < r[-1]
           else "every pair points the same way, at this size and load")
print(f"frame on/off over {n} pairs: min {r[0]:.3f}, median {statistics.median(r):.3f}, "
      f"max {r[-1]:.3f} ({verdict})")
PY
  echo "(uptime: $(uptime | sed 's/^ *//'))"
}
echo "== HRPP on against off (study/bench.py: same binary, seed and image, $pairs off/on"
echo "   pairs interleaved; ratios of device time per ray class and frame, < 1: HRPP faster)"
/usr/bin/python3 -m study bench --hrpp "$hrpp" --scenes builtin:cornell --size 256x256 \
  --spp 8 --repeat "$pairs" --images build/demo/default
spread default
/usr/bin/python3 -m study bench --hrpp "$hrpp" --scenes builtin:cornell --size 256x256 \
  --spp 8 --repeat "$pairs" --flags "--hrpp-mode exact" --images build/demo/exact
spread exact
oiiotool build/demo/default/builtin_cornell_off0.exr build/demo/exact/builtin_cornell_on0.exr \
  build/demo/default/builtin_cornell_on0.exr --mosaic 3x1 --colorconvert linear sRGB \
  -o build/demo/hrpp_off_exact_speculative.png
echo "(HRPP off | exact | speculative (the default), side by side:"
echo " build/demo/hrpp_off_exact_speculative.png; exact renders HRPP off's image bit for bit)"
