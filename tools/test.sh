#!/usr/bin/env bash
# Set up, build (warnings are errors) and run the whole test suite with CTest.
# Usage: tools/test.sh [extra ctest arguments, e.g. -L unit]
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
tools/build.sh ci
ctest --preset ci -j"$(nproc)" "$@"
