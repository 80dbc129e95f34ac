#!/usr/bin/env bash
# Configures and builds hrpp with a CMake preset (default: release; CI uses "ci", -Werror).
# Usage: tools/build.sh [PRESET]
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-release}
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" -j"$(nproc)"
