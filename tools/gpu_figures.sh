#!/usr/bin/env bash
# The one check of a machine with a real GPU: the figures it adds beside lavapipe's, in one run
# of at most --deadline seconds (default 480), written into one directory (--out) and, when $OUT
# is set (the device machine's folder of files that come back), packed into one archive there,
# $OUT/gpu_figures.tar.gz. Steps, each with its own time limit, so a slow or failing one leaves
# the others' figures:
#   1. the machine: device, driver, subgroup size, float denormals, every memory type and heap
#      (vulkaninfo --summary when it is there: the kit carries one), the ray-tracing extensions it
#      lists, where each role's buffers live under --memory staged and mapped;
#   2. hrpp bench on bunny, lamborghini and dragon with --memory staged and with --memory mapped:
#      the device against Embree on all the machine's threads per query kind, answers checked
#      against the CPU reference (a mismatch fails the step);
#   3. the query kinds' order in one process (--kinds ao, primary,ao, ao,primary, diffuse,ao) for
#      both memory modes, and on bunny's rays hrpp trace against the independent Embree harness;
#   4. per-kernel times: hrpp render bunny with HRPP on under each memory mode (render --stats),
#      twice, interleaved;
#   5. study/bench.py at its defaults (the adaptive predictor): HRPP on against off;
#   6. every GPU test binary (CTest label gpu), each alone;
#   7. study/bench.py with every ray predicted (configs/hrpp/every-ray.json);
#   8. study/model.py: this device's cost per operation fitted, its held-out error and where
#      prediction would pay here (docs/EXPERIMENTS.md, "The cost model");
#   9. step 7 again with the paper's fallback (configs/hrpp/every-ray-root.json): what the skip fallback
#      (step 7, the default) saves in time on this device;
#  10. where the device has VK_KHR_ray_query (step 1 says), the driver's ray queries beside the
#      BVH kernels and Embree, with HRPP in front of them (hrpp bench --tracer rayquery --hrpp on
#      on bunny, lamborghini and dragon, and python3 -m study bench --tracer rayquery); elsewhere
#      one line saying that the device has none;
#  11. MICRO'21's predictor as submitted (configs/hrpp/micro21.json: 2 SM tables of 1024
#      entries) on the scenes of step 2: its stage's kernel time against HRPP off, every ray
#      probing.
# Exit status 1 when a step failed (the figures are still written); 2 on bad options.
#
# On the GPU machine (no network, a fresh checkout), from the repository's root:
#   tools/gpu_figures.sh                      # uses build/portable/gpu_kit.tar.xz when there
# Made beforehand on a Debian 12 machine, after `cmake --preset portable && cmake --build
# --preset portable`:
#   tools/gpu_figures.sh --pack               # writes build/portable/gpu_kit.tar.xz
# The kit holds the portable build's hrpp, bench_embree_harness and GPU test binaries (stripped),
# every shared library they need beyond glibc and libstdc++ (Embree, TBB, the Vulkan loader,
# glvnd's libraries, which NVIDIA's driver loads), the Khronos validation layer,
# vulkaninfo, and the dragon when scenes/fetched has it. Run there, the script unpacks it in
# place, points LD_LIBRARY_PATH, VK_LAYER_PATH and (when unset) VK_DRIVER_FILES at it and the
# NVIDIA driver (the first manifest under which its vulkaninfo sees a GPU), and links the
# build's source path to this checkout when they differ, since the test binaries name their
# data by the path they were built at.
#
# Usage: tools/gpu_figures.sh [--kit FILE] [--bin DIR] [--tests DIR] [--out DIR] [--repeat N]
#                             [--deadline S] [--quick] [--steps LIST]
#        tools/gpu_figures.sh --pack [--build DIR] [--kit FILE]
#   --kit FILE    the kit to use or write (default build/portable/gpu_kit.tar.xz)
#   --bin DIR     where hrpp is (default: the kit's, else build/portable/host, else
#                 build/release/host)
#   --tests DIR   where the GPU test binaries are (default: beside --bin; none: skip)
#   --out DIR     where the figures go (default build/gpu_figures)
#   --repeat N    hrpp bench's timed runs per tracer and batch (default 5)
#   --deadline S  start no step after S seconds, and cut a running one there (default 480)
#   --steps LIST  only these steps, comma-separated (default all; the machine's is always run):
#                 bench order trace render hrpp_bench tests every_ray model root rayquery (order and trace
#                 use the rays of bench's bunny run, which they run when bench is not named)
#   --quick       small sizes and one scene: a run of the whole script on lavapipe in about a
#                 minute (the test suite's gpu_figures_quick)
#   --pack        write the kit (above) from --build (default build/portable)
# PYTHON names the Python that runs study/bench.py and study/model.py (default python3,
# with numpy; without OpenImageIO hrpp_bench.py reads the uncompressed EXR files of a portable
# build, and without matplotlib the model draws no figure).
set -uo pipefail
cd "$(dirname "$0")/.."

kit=build/portable/gpu_kit.tar.xz
bin=""
tests=""
out=build/gpu_figures
repeat=5
deadline=480
quick=0
all_steps="bench order trace render hrpp_bench tests every_ray model root rayquery micro21"
steps=",${all_steps// /,},"
pack=0
build=build/portable
while [[ $# -gt 0 ]]; do
  case "$1" in
    --kit) kit="${2:?--kit needs a file}"; shift 2 ;;
    --bin) bin="${2:?--bin needs a directory}"; shift 2 ;;
    --tests) tests="${2:?--tests needs a directory}"; shift 2 ;;
    --out) out="${2:?--out needs a directory}"; shift 2 ;;
    --repeat) repeat="${2:?--repeat needs a number}"; shift 2 ;;
    --deadline) deadline="${2:?--deadline needs seconds}"; shift 2 ;;
    --quick) quick=1; shift ;;
    --steps) steps=",${2:?--steps needs a list}," ; shift 2 ;;
    --pack) pack=1; shift ;;
    --build) build="${2:?--build needs a directory}"; shift 2 ;;
    --help|-h) sed -n '2,/^set /p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "gpu_figures: unknown option $1 (--help)" >&2; exit 2 ;;
  esac
done
[[ "$repeat" =~ ^[1-9][0-9]*$ ]] || { echo "gpu_figures: --repeat $repeat: not a count" >&2; exit 2; }
[[ "$deadline" =~ ^[1-9][0-9]*$ ]] || { echo "gpu_figures: --deadline $deadline: not seconds" >&2; exit 2; }
for name in ${steps//,/ }; do
  [[ " $all_steps " == *" $name "* ]] || { echo "gpu_figures: --steps: no step $name (--help)" >&2; exit 2; }
done
want() { [[ "$steps" == *",$1,"* ]]; }

# The GPU test binaries, as tests/CMakeLists.txt declares them (label gpu).
gpu_tests() { grep -oP 'hrpp_test\(\K\w+(?= gpu)' tests/CMakeLists.txt; }

# --pack: the kit, paths relative to the repository's root.
pack_kit() {
  local lib b
  [ -x "$build/host/hrpp" ] || { echo "gpu_figures: no hrpp in $build/host (--build)" >&2; exit 2; }
  stage=$(mktemp -d)
  trap 'rm -rf "$stage"' EXIT
  mkdir -p "$stage/$build"/{host,bench,tests,lib,layers}
  local bins=("$build/host/hrpp")
  [ -x "$build/bench/bench_embree_harness" ] && bins+=("$build/bench/bench_embree_harness")
  for t in $(gpu_tests); do [ -x "$build/tests/$t" ] && bins+=("$build/tests/$t"); done
  for b in "${bins[@]}"; do strip -o "$stage/$b" "$b"; done
  command -v vulkaninfo >/dev/null && cp "$(command -v vulkaninfo)" "$stage/$build/host/"
  # Every library they load but glibc's and the C++ runtime (the GPU machine has newer ones).
  for lib in $(ldd "${bins[@]}" "$stage/$build/host/"* 2>/dev/null | grep -oP '=> \K/\S+' | sort -u); do
    case "$(basename "$lib")" in
      libc.so*|libm.so*|libpthread.so*|libdl.so*|librt.so*|ld-linux*|libresolv.so*) ;;
      libstdc++.so*|libgcc_s.so*) ;;
      *) cp -L "$lib" "$stage/$build/lib/" ;;
    esac
  done
  for lib in libVkLayer_khronos_validation.so libGLX.so.0 libGLdispatch.so.0 libEGL.so.1 \
             libGL.so.1 libOpenGL.so.0 libGLESv2.so.2; do
    cp -L "/usr/lib/x86_64-linux-gnu/$lib" "$stage/$build/lib/" 2>/dev/null ||
      echo "gpu_figures: $lib not found (Debian packages vulkan-validationlayers, libglx0," \
        "libegl1, libgl1, libopengl0, libgles2)" >&2
  done
  cp /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json "$stage/$build/layers/" 2>/dev/null
  pwd > "$stage/$build/source_dir"
  if [ -f scenes/fetched/stanford_dragon.glb ]; then
    mkdir -p "$stage/scenes/fetched" && cp scenes/fetched/stanford_dragon.glb "$stage/scenes/fetched/"
  fi
  XZ_OPT=-T0 tar -cJf "$kit" -C "$stage" .
  echo "gpu_figures: wrote $kit ($(du -h "$kit" | cut -f1)); on the GPU machine: tools/gpu_figures.sh"
}

if [ "$pack" = 1 ]; then
  pack_kit
  exit 0
fi

# untar -t | -x: lists or unpacks the kit (xz, or Python's lzma where there is no xz).
untar() {
  if command -v xz >/dev/null; then
    tar "${1}Jf" "$kit"
  else
    "${PYTHON:-python3}" - "$1" "$kit" <<'PY'
import sys, tarfile
with tarfile.open(sys.argv[2]) as t:
    if sys.argv[1] == "-t":
        print("\n".join(t.getnames()))
    else:
        t.extractall()
PY
  fi
}

# try_manifests VULKANINFO MANIFEST...: exports VK_DRIVER_FILES as the first manifest under which
# vulkaninfo sees a GPU; notes why each other one failed.
try_manifests() {
  local vi=$1 icd; shift
  for icd in "$@"; do
    if VK_DRIVER_FILES="$icd" timeout 30 "$vi" --summary 2>/dev/null |
        grep -q "deviceType *= PHYSICAL_DEVICE_TYPE_\(DISCRETE\|INTEGRATED\)_GPU"; then
      export VK_DRIVER_FILES="$icd"
      driver_note+="Vulkan driver: $icd"$'\n'
      return 0
    fi
    driver_note+="no GPU through $icd: $(VK_DRIVER_FILES="$icd" VK_LOADER_DEBUG=error \
      timeout 30 "$vi" --summary 2>&1 | grep -m 1 -E "ERROR|error")"$'\n'
  done
  return 1
}

# find_driver KITDIR: unless VK_DRIVER_FILES is set, the first NVIDIA manifest under which the
# kit's vulkaninfo sees a GPU: the installed manifests, then ones naming each libGLX_nvidia
# found by its full path; when none does and this is root, the same again after ldconfig. The
# driver's own folder goes on LD_LIBRARY_PATH: its Vulkan library loads the driver's other
# libraries by name. (On one H200 machine none was found until glvnd's libraries were installed
# and ldconfig run; which of the two it took is not known: the kit carries those libraries.)
find_driver() {
  local vi="$1/host/vulkaninfo" icd lib n=0 candidates=()
  local nv=/usr/local/nvidia/lib64  # the driver's folder on the lent machines
  [ -d "$nv" ] && export LD_LIBRARY_PATH="$LD_LIBRARY_PATH:$nv"
  [ -z "${VK_DRIVER_FILES:-}" ] || return 0
  for icd in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json \
             /usr/share/vulkan/icd.d/nvidia_icd.json /etc/vulkan/icd.d/nvidia_icd.json; do
    [ -f "$icd" ] && candidates+=("$icd")
  done
  for lib in "$nv" /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/lib; do
    lib="$lib/libGLX_nvidia.so.0"
    [ -f "$lib" ] || continue
    n=$((n + 1))
    printf '{"file_format_version": "1.0.1",
             "ICD": {"library_path": "%s", "api_version": "1.3.0"}}\n' "$lib" > "$1/nvidia_icd_$n.json"
    candidates+=("$PWD/$1/nvidia_icd_$n.json")
  done
  if [ ! -x "$vi" ]; then
    [ ${#candidates[@]} -gt 0 ] && export VK_DRIVER_FILES="${candidates[0]}"
    return 0
  fi
  try_manifests "$vi" "${candidates[@]}" && return 0
  if [ ${#candidates[@]} -gt 0 ] && [ "$(id -u)" = 0 ] && command -v ldconfig >/dev/null; then
    driver_note+="ldconfig, then again"$'\n'
    ldconfig && try_manifests "$vi" "${candidates[@]}" && return 0
  fi
  [ ${#candidates[@]} -gt 0 ] || driver_note+="no NVIDIA Vulkan manifest or libGLX_nvidia"$'\n'
}
driver_note=""

# The kit, when there and no --bin was given: unpacked in place, its libraries and layer used.
use_kit() {
  local kdir src
  kdir=$(untar -t | grep -oP '^\./\K.*(?=/host/hrpp$)')  # the whole list: no SIGPIPE
  [ -n "$kdir" ] || return 1
  untar -x || return 1
  bin="$kdir/host"
  export LD_LIBRARY_PATH="$PWD/$kdir/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  export VK_LAYER_PATH="$PWD/$kdir/layers"
  find_driver "$kdir"
  # The test binaries read scenes/ and tests/data/ by the source path they were built at.
  src=$(cat "$kdir/source_dir")
  if [ "$src" != "$PWD" ] && [ ! -e "$src" ]; then
    mkdir -p "$(dirname "$src")" && ln -s "$PWD" "$src" ||
      echo "gpu_figures: cannot link $src to this checkout: tests reading scene files fail"
  fi
}

if [ -z "$bin" ]; then
  if [ -f "$kit" ]; then
    use_kit || { echo "gpu_figures: $kit: not a kit of tools/gpu_figures.sh --pack" >&2; exit 2; }
  elif [ -x build/portable/host/hrpp ]; then
    bin=build/portable/host
  else
    bin=build/release/host
  fi
fi
[ -n "$tests" ] || tests="$bin/../tests"
hrpp="$bin/hrpp"
[ -x "$hrpp" ] || { echo "gpu_figures: no hrpp at $hrpp (--bin, --kit)" >&2; exit 2; }
rm -rf "$out"
mkdir -p "$out"
log="$out/log.txt"
exec 3>&1 4>&2 > >(tee -a "$log") 2>&1
tee_pid=$!

failed=()
step() { echo; echo "=== $* ($(date -u +%T), ${SECONDS} s, load $(cut -d' ' -f1 /proc/loadavg))"; }
# limit S NAME CMD...: runs CMD for at most S seconds and never past the deadline; a failure
# (124: cut) is reported and remembered under NAME.
limit() {
  local s=$1 name=$2 left=$((deadline - SECONDS)) rc; shift 2
  if [ "$left" -le 0 ]; then
    echo "skipped: past the ${deadline} s deadline"
    failed+=("$name (skipped)")
    return 124
  fi
  timeout $((s < left ? s : left)) "$@"
  rc=$?
  [ "$rc" = 0 ] || { echo "exit $rc"; failed+=("$name (exit $rc)"); }
  return "$rc"
}

scenes=(bunny lamborghini dragon)
[ -f scenes/fetched/stanford_dragon.glb ] || scenes=(bunny lamborghini)
modes=(staged mapped)
if [ "$quick" = 1 ]; then
  scenes=(bunny)
  bench_args=(--rays 16384 --repeat 1 --check-rays 1024)
  order_args=(--rays 16384 --repeat 1 --check-rays 256)
  render_args=(--size 64x64 --spp 2)
  hb_args=(--quick --scenes cornell)
  model_args=(--scenes builtin:cornell,teapot --size 48x48 --spp 1 --repeat 1)
else
  bench_args=(--repeat "$repeat" --check-rays 20000)
  order_args=(--repeat "$repeat" --check-rays 1000)
  render_args=(--size 1024x1024 --spp 4)
  hb_args=(--repeat 2)
  model_args=(--size 512x512 --spp 4 --repeat 1)
fi

step "machine"
nproc; uname -r
printf '%s' "$driver_note"
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv
vulkaninfo=$(command -v vulkaninfo || echo "$bin/vulkaninfo")
[ -x "$vulkaninfo" ] && timeout 30 "$vulkaninfo" --summary > "$out/vulkaninfo.txt" 2>&1 &&
  grep -E "deviceName|driverName|driverInfo|apiVersion" "$out/vulkaninfo.txt"
[ -x "$vulkaninfo" ] && timeout 30 "$vulkaninfo" 2>/dev/null |
  sed -n '/VkPhysicalDeviceMemoryProperties/,/^VkPhysicalDeviceFeatures/p' > "$out/memory_types.txt"
# The driver's own ray tracing (the ray-query tracer needs the first two).
[ -x "$vulkaninfo" ] && { timeout 30 "$vulkaninfo" 2>/dev/null |
  grep -oE "VK_KHR_(ray_query|acceleration_structure|ray_tracing_pipeline)" | sort -u |
  tr '\n' ' '; echo; } | sed 's/^$/no ray-tracing extension/' | tee "$out/ray_tracing.txt"

rays=$(mktemp -d)
trap 'rm -rf "$rays"' EXIT
for scene in "${scenes[@]}"; do
  for mode in "${modes[@]}"; do
    # Bench's bunny run saves the rays that the order and trace steps use.
    want bench || { [ "$scene/$mode" = bunny/staged ] && { want order || want trace; }; } ||
      continue
    step "hrpp bench $scene --memory $mode"
    save=(); [ "$scene" = bunny ] && [ "$mode" = staged ] && save=(--save-rays "$rays")
    limit 60 "bench $scene $mode" "$hrpp" bench "$scene" --memory "$mode" "${bench_args[@]}" \
      "${save[@]}" --json "$out/bench_${scene}_$mode.json"
  done
done

if [ -f "$rays/ao.rays" ] && want order; then
  for mode in "${modes[@]}"; do
    step "bunny --memory $mode: the order of the query kinds in one process"
    for kinds in ao primary,ao ao,primary diffuse,ao; do
      echo "--kinds $kinds"
      limit 30 "order $kinds $mode" "$hrpp" bench bunny --memory "$mode" --kinds "$kinds" \
        "${order_args[@]}" --no-embree --json "$out/order_${kinds/,/_}_$mode.json" > "$rays/out"
      grep -E "^(memory|primary|ao|diffuse) |  gpu " "$rays/out"
    done
  done
fi
# bench/README.md, "Is hrpp bench's Embree figure right?": Embree alone on the same rays.
if [ -f "$rays/ao.rays" ] && want trace; then
  harness="$bin/bench_embree_harness"
  [ -x "$harness" ] || harness="$bin/../bench/bench_embree_harness"
  if [ -x "$harness" ] && [ -f "$rays/triangles.bin" ]; then
    for kind in primary ao; do
      step "bunny $kind: hrpp trace and the independent Embree harness on the same rays"
      any=(); [ "$kind" = ao ] && any=(--any-hit)
      limit 30 "trace $kind" "$hrpp" trace bunny --rays "$rays/$kind.rays" --hits "$rays/hits" \
        "${any[@]}" --repeat 5 --stats "$out/trace_$kind.json"
      limit 30 "harness $kind" "$harness" --triangles "$rays/triangles.bin" \
        --rays "$rays/$kind.rays" "${any[@]}" --repeat 5
    done
  fi
fi

# Twice per memory mode, interleaved: a first render can meet the GPU at idle clocks.
want render && for round in 1 2; do
  for mode in "${modes[@]}"; do
    step "per-kernel times: hrpp render bunny --hrpp on --memory $mode, round $round"
    limit 60 "render $mode" "$hrpp" render bunny --hrpp on --memory "$mode" "${render_args[@]}" \
      --out "$out/render.exr" --stats "$out/render_${mode}_$round.json"
    rm -f "$out/render.exr"
  done
done

if want hrpp_bench; then
  step "hrpp_bench.py, the default predictor"
  limit 120 "hrpp_bench default" "${PYTHON:-python3}" -m study bench --hrpp "$hrpp" \
    "${hb_args[@]}" --json "$out/hrpp_bench_default.json"
fi

if [ -d "$tests" ] && want tests; then
  step "GPU tests (each binary alone)"
  : > "$out/tests.txt"
  for t in $(gpu_tests); do
    [ -x "$tests/$t" ] || { echo "$t: not built" | tee -a "$out/tests.txt"; continue; }
    filter=()
    # --quick: every binary starts and lists its tests; one runs a few.
    if [ "$quick" = 1 ]; then
      filter=(--gtest_list_tests)
      [ "$t" = gpu_trace_test ] && filter=(--gtest_filter='VulkanContext.*')
    fi
    limit 90 "$t" "$tests/$t" --gtest_brief=1 "${filter[@]}" > "$out/$t.log" 2>&1
    rc=$?
    summary=$(grep -E "^\[  (PASSED|FAILED)  \]|^\[  SKIPPED \]" "$out/$t.log" | tr '\n' ' ')
    echo "$t: exit $rc $summary" | tee -a "$out/tests.txt"
    grep -E "^\[  FAILED  \]|Failure|Expected|Which is|actual" "$out/$t.log" | head -40 >> "$out/tests.txt"
    [ "$rc" = 0 ] && rm -f "$out/$t.log"  # a failing binary keeps its whole log
  done
fi

if want every_ray; then
  step "hrpp_bench.py, every ray predicted (configs/hrpp/every-ray.json)"
  limit 90 "hrpp_bench every ray" "${PYTHON:-python3}" -m study bench --hrpp "$hrpp" \
    "${hb_args[@]}" --repeat 1 --flags "--hrpp-config configs/hrpp/every-ray.json" --json "$out/hrpp_bench_every_ray.json"
fi

if want model; then
  step "hrpp_model.py: this device's costs per operation and where prediction would pay"
  limit 120 "hrpp_model" "${PYTHON:-python3}" -m study model --hrpp "$hrpp" "${model_args[@]}" \
    --runs "$rays/model" --json "$out/hrpp_model.json" --figure "$out/hrpp_model.png"
fi

if want root; then
  step "hrpp_bench.py, every ray predicted, the paper's fallback (configs/hrpp/every-ray-root.json)"
  limit 90 "hrpp_bench every ray, root" "${PYTHON:-python3}" -m study bench --hrpp "$hrpp" \
    "${hb_args[@]}" --repeat 1 --flags "--hrpp-config configs/hrpp/every-ray-root.json" \
    --json "$out/hrpp_bench_every_ray_root.json"
fi

if want rayquery; then
  step "the driver's ray queries (--tracer rayquery), with HRPP in front"
  if grep -q VK_KHR_ray_query "$out/ray_tracing.txt" 2>/dev/null; then
    for scene in "${scenes[@]}"; do
      limit 90 "rayquery bench $scene" "$hrpp" bench "$scene" --tracer rayquery --hrpp on \
        --warn-mismatches "${bench_args[@]}" --json "$out/rayquery_$scene.json"
    done
    limit 90 "hrpp_bench rayquery" "${PYTHON:-python3}" -m study bench --hrpp "$hrpp" \
      "${hb_args[@]}" --repeat 1 --tracer rayquery --json "$out/hrpp_bench_rayquery.json"
  else
    echo "no VK_KHR_ray_query on this device ($(cat "$out/ray_tracing.txt" 2>/dev/null)):" \
      "the ray-query tracer cannot run here"
  fi
fi

if want micro21; then
  step "MICRO'21's predictor as submitted (configs/hrpp/micro21.json)"
  for scene in "${scenes[@]}"; do
    limit 60 "micro21 bench $scene" "$hrpp" bench "$scene" --hrpp-config configs/hrpp/micro21.json \
      --no-embree "${bench_args[@]}" --json "$out/micro21_$scene.json"
  done
fi

step "done"
if [ "${#failed[@]}" -gt 0 ]; then
  echo "failed: ${failed[*]}"
else
  echo "every step passed"
fi
exec 1>&3 2>&4
wait "$tee_pid"  # the log is whole before it is packed
if [ -n "${OUT:-}" ]; then
  tar -czf "$OUT/gpu_figures.tar.gz" -C "$(dirname "$out")" "$(basename "$out")"
  echo "packed into $OUT/gpu_figures.tar.gz"
fi
[ "${#failed[@]}" = 0 ]
