#!/usr/bin/env bash
# Runs the libFuzzer targets (fuzz/) of the "asan" build for a bounded time each, from the seed
# corpora (fuzz/corpus/<target>/, the bad-input corpus tests/data/bad/ and, for glTF, the
# encodings corpus tests/data/gltf_encodings/: quantized, meshopt and Draco files). New inputs go
# to build/asan/fuzz-corpus/<target>/, crashes to build/asan/fuzz-findings/. Exit status non-zero
# on any crash, sanitizer report, leak or timeout.
# Usage: tools/fuzz.sh [SECONDS_PER_TARGET (default 30)] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(fuzz_gltf fuzz_manifest fuzz_pbrt fuzz_mesh)
build=build/asan
[ -x "$build/fuzz/fuzz_gltf" ] || tools/build.sh asan
mkdir -p "$build/fuzz-findings"
status=0
for t in "${targets[@]}"; do
  corpus="$build/fuzz-corpus/$t"
  mkdir -p "$corpus"
  case $t in
    fuzz_gltf) seeds=(fuzz/corpus/gltf tests/data/bad/gltf tests/data/gltf_encodings) ;;
    fuzz_manifest) seeds=(fuzz/corpus/manifest tests/data/bad/manifest) ;;
    fuzz_pbrt) seeds=(fuzz/corpus/pbrt) ;;
    fuzz_mesh) seeds=(fuzz/corpus/mesh) ;;
    *) echo "fuzz: unknown target $t" >&2; exit 1 ;;
  esac
  echo "fuzz: $t for ${seconds}s"
  # -timeout: an input that takes more than 10 s is a hang; -rss_limit_mb: 2 GiB is a leak or
  # an unchecked allocation (the loaders must refuse absurd sizes first).
  if ! ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      LSAN_OPTIONS=suppressions=tests/sanitizers/lsan.supp:print_suppressions=0 \
      ASAN_SYMBOLIZER_PATH=/usr/bin/llvm-symbolizer \
      "$build/fuzz/$t" "$corpus" "${seeds[@]}" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
      -artifact_prefix="$build/fuzz-findings/$t-" 2>"$build/fuzz-$t.log"; then
    tail -n 60 "$build/fuzz-$t.log" >&2
    echo "fuzz: $t FAILED (log: $build/fuzz-$t.log, inputs: $build/fuzz-findings/)" >&2
    status=1
  else
    grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb|^Done" "$build/fuzz-$t.log" || true
  fi
done
exit $status
