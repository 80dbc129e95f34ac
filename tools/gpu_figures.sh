#!/usr/bin/env bash
# The figures a machine with a real GPU adds beside lavapipe's, in one run:
#   1. hrpp bench on bunny, lamborghini and dragon: the Vulkan device against Embree on all the
#      machine's threads, the same rays (issue 12's GPU/Embree ratios), answers checked against
#      the CPU reference (--strict); on bunny's rays, also hrpp trace and the independent Embree
#      harness (bench_embree_harness, beside hrpp or in the build tree's bench/), then the
#      query kinds' order in one process and the rays per invocation;
#   2. tools/hrpp_bench.py: HRPP on against off per ray class and frame on the stand-ins, with
#      the default (adaptive) predictor;
#   3. the GPU test binaries (label gpu): the device's answers against the CPU reference;
#   4. tools/hrpp_bench.py with every ray predicted (--hrpp-adaptive off), one pair per scene.
# Each step has its own time limit, so a slow or failing one leaves the others' figures.
# Everything is written under --out (log.txt, bench_SCENE.json, hrpp_bench_*.json, tests.txt).
#
# Usage: tools/gpu_figures.sh [--bin DIR] [--tests DIR] [--out DIR] [--repeat N]
#                             [--deadline S] [--quick]
#   --bin DIR     where hrpp is (default build/release/host)
#   --tests DIR   where the GPU test binaries are (default build/release/tests; none: skip)
#   --out DIR     where the figures go (default build/gpu_figures)
#   --repeat N    hrpp bench's timed runs per tracer and batch (default 5)
#   --deadline S  start no step after S seconds, and cut a running one there (default 3600)
#   --quick       small sizes (a dry run of the script on lavapipe)
# PYTHON names the Python that runs tools/hrpp_bench.py (default python3, with numpy; without
# OpenImageIO it reads the uncompressed EXR files of a portable build).
set -uo pipefail
cd "$(dirname "$0")/.."

bin=build/release/host
tests=build/release/tests
out=build/gpu_figures
repeat=5
deadline=3600
quick=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --bin) bin="${2:?--bin needs a directory}"; shift 2 ;;
    --tests) tests="${2:?--tests needs a directory}"; shift 2 ;;
    --out) out="${2:?--out needs a directory}"; shift 2 ;;
    --repeat) repeat="${2:?--repeat needs a number}"; shift 2 ;;
    --deadline) deadline="${2:?--deadline needs seconds}"; shift 2 ;;
    --quick) quick=1; shift ;;
    --help|-h) sed -n '2,/^set /p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "gpu_figures: unknown option $1 (--help)" >&2; exit 2 ;;
  esac
done
[[ "$repeat" =~ ^[1-9][0-9]*$ ]] || { echo "gpu_figures: --repeat $repeat: not a count" >&2; exit 2; }
[[ "$deadline" =~ ^[1-9][0-9]*$ ]] || { echo "gpu_figures: --deadline $deadline: not seconds" >&2; exit 2; }
hrpp="$bin/hrpp"
[ -x "$hrpp" ] || { echo "gpu_figures: no hrpp at $hrpp (--bin)" >&2; exit 2; }
mkdir -p "$out"
log="$out/log.txt"
exec > >(tee -a "$log") 2>&1

step() { echo; echo "=== $* ($(date -u +%T), ${SECONDS} s, load $(cut -d' ' -f1 /proc/loadavg))"; }
# limit S CMD...: runs CMD for at most S seconds and never past the deadline; 124 when cut.
limit() {
  local s=$1 left=$((deadline - SECONDS)); shift
  [ "$left" -le 0 ] && { echo "skipped: past the ${deadline} s deadline"; return 124; }
  timeout $((s < left ? s : left)) "$@"
}

if [ "$quick" = 1 ]; then
  bench_args=(--rays 65536 --repeat 1 --check-rays 4096)
  order_args=(--rays 65536 --repeat 1)
  hb_args=(--quick --scenes cornell,bunny)
else
  bench_args=(--repeat "$repeat" --check-rays 100000)
  order_args=(--repeat "$repeat")
  hb_args=(--repeat 2)
fi

step "machine"
nproc; uname -r
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv
"$hrpp" --version 2>/dev/null || true

rays=$(mktemp -d)
trap 'rm -rf "$rays"' EXIT
for scene in bunny lamborghini dragon; do
  step "hrpp bench $scene"
  save=(); [ "$scene" = bunny ] && save=(--save-rays "$rays")
  limit 150 "$hrpp" bench "$scene" "${bench_args[@]}" "${save[@]}" --strict \
    --json "$out/bench_$scene.json"
  echo "exit $?"
done

# bench/README.md, "Is hrpp bench's Embree figure right?": Embree alone on the same rays.
harness="$bin/bench_embree_harness"  # beside hrpp, or in the build tree's bench/
[ -x "$harness" ] || harness="$bin/../bench/bench_embree_harness"
if [ -x "$harness" ] && [ -f "$rays/triangles.bin" ]; then
  for kind in primary ao diffuse; do
    step "bunny $kind: hrpp trace and the independent Embree harness on the same rays"
    any=(); [ "$kind" = ao ] && any=(--any-hit)
    limit 60 "$hrpp" trace bunny --rays "$rays/$kind.rays" --hits "$rays/hits" "${any[@]}" --repeat 5
    limit 60 "$harness" --triangles "$rays/triangles.bin" \
      --rays "$rays/$kind.rays" "${any[@]}" --repeat 5
  done
fi

if [ -f "$rays/ao.rays" ]; then
  step "bunny: the order of the query kinds in one process, and rays per invocation"
  for kinds in ao primary,ao ao,primary; do
    echo "--kinds $kinds"
    limit 60 "$hrpp" bench bunny --kinds "$kinds" "${order_args[@]}" --no-embree \
      --check-rays 1000 | grep -E "^(memory|primary|ao) |  gpu "
  done
  for n in 1 4 16 64; do
    echo "--rays-per-invocation $n"
    limit 60 "$hrpp" trace bunny --rays "$rays/ao.rays" --hits "$rays/hits" --any-hit \
      --repeat 5 --rays-per-invocation "$n" | grep -E "^kernel"
  done
fi

step "hrpp_bench.py, the default predictor"
limit 240 "${PYTHON:-python3}" tools/hrpp_bench.py --hrpp "$hrpp" "${hb_args[@]}" \
  --json "$out/hrpp_bench_default.json"
echo "exit $?"
if [ -d "$tests" ]; then
  step "GPU tests (each binary alone, 120 s at most)"
  : > "$out/tests.txt"
  # The binaries of label gpu, as tests/CMakeLists.txt declares them.
  for t in $(grep -oP 'hrpp_test\(\K\w+(?= gpu)' tests/CMakeLists.txt); do
    [ -x "$tests/$t" ] || { echo "$t: not built" | tee -a "$out/tests.txt"; continue; }
    limit 120 "$tests/$t" --gtest_brief=1 > "$out/$t.log" 2>&1
    rc=$?
    summary=$(grep -E "^\[  (PASSED|FAILED)  \]" "$out/$t.log" | tr '\n' ' ')
    echo "$t: exit $rc $summary" | tee -a "$out/tests.txt"
    grep -E "^\[  FAILED  \]|Failure|Expected|Which is|actual" "$out/$t.log" | head -40 >> "$out/tests.txt"
    [ "$rc" = 0 ] && rm -f "$out/$t.log"  # a failing binary keeps its whole log
  done
fi
step "hrpp_bench.py, every ray predicted (--hrpp-adaptive off)"
limit 240 "${PYTHON:-python3}" tools/hrpp_bench.py --hrpp "$hrpp" "${hb_args[@]}" --repeat 1 \
  --flags "--hrpp-adaptive off" --json "$out/hrpp_bench_every_ray.json"
echo "exit $?"

step "done"
