#!/usr/bin/env bash
# Set up, build (warnings are errors) and run the whole test suite with CTest (GPU tests under
# the Vulkan validation layer: any message fails), then the sanitizer build's CPU tests and a
# bounded fuzzing run.
# Usage: tools/test.sh [extra ctest arguments, e.g. -L unit]
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
tools/build.sh ci
ctest --preset ci -j"$(nproc)" "$@"
# The CPU tests (label unit; the asan build preset lists their executables) again under
# ASan + UBSan (clang), then each libFuzzer target for 30 s (tools/fuzz.sh).
# HRPP_TEST_SANITIZERS=0 skips both (e.g. for a quick local run).
if [ "${HRPP_TEST_SANITIZERS:-1}" != 0 ]; then
  tools/build.sh asan
  ctest --preset asan -j"$(nproc)"
  tools/fuzz.sh 30
fi
