#!/usr/bin/env bash
# Checks the glTF loader's verdicts against Khronos' glTF Validator (the spec's own): every glTF
# file of the committed scenes, the encodings corpus, the fuzz seeds and the bad-input corpus is
# validated (npm gltf-validator, one node process a file, tests/gltf/validate.mjs; POSITION
# min/max is not required) and loaded with `hrpp scene`. The validator is installed into a
# scratch directory (NPM_TOOLS, default /tmp/hrpp-npm-tools; needs node and npm), never the
# repository. One line per file:
#   ERRORS FIRST_ERROR_CODE  loads | refused | limit  FILE
# ("limit": refused by design: no triangles, an unsupported required extension, a size limit,
# vertices out of float range). A disagreement is a valid file that hrpp refuses (exit status 1)
# or a file with validator errors that hrpp loads (reported only: the loader reads what it can).
# Usage: tests/gltf/validate.sh [HRPP_BINARY (default build/ci/host/hrpp)]
set -euo pipefail

root="$(cd "$(dirname "$0")/../.." && pwd)"
hrpp="${1:-$root/build/ci/host/hrpp}"
tools="${NPM_TOOLS:-/tmp/hrpp-npm-tools}"
validator="$tools/node_modules/gltf-validator"
if [ ! -f "$validator/index.js" ]; then
  mkdir -p "$tools"
  (cd "$tools" && npm install --no-save --silent gltf-validator@2.0.0-dev.3.10)
fi

mapfile -t files < <(cd "$root" && ls scenes/meshes/*.glb tests/data/gltf_encodings/*.gl* \
  fuzz/corpus/gltf/* tests/data/bad/gltf/* | grep -v '\.bin$')
# Refusals of valid files by design: nothing to render, an extension it lacks, its size limits.
by_design='no triangles|are degenerate|required by the file but not supported|more than [0-9]+ '
by_design+='(times|triangles)|larger than [0-9]+ on a side|out of float range'
refused_valid=0
disagree=()
while IFS=$'\t' read -r errors code file; do
  if message=$("$hrpp" scene "$root/$file" 2>&1 >/dev/null); then
    verdict=loads
  elif grep -qE "$by_design" <<<"$message"; then
    verdict=limit  # refused by design: valid glTF that hrpp cannot render or will not expand
  else
    verdict=refused
  fi
  printf '%-6s %-34s %-8s %s\n' "$errors" "$code" "$verdict" "$file"
  if [ "$errors" = 0 ] && [ "$verdict" = refused ]; then
    disagree+=("valid, refused: $file")
    refused_valid=$((refused_valid + 1))
  elif [ "$errors" != 0 ] && [ "$verdict" = loads ]; then
    disagree+=("invalid ($code), loads: $file")
  fi
done < <(cd "$root" && for f in "${files[@]}"; do
  node "$root/tests/gltf/validate.mjs" "$validator" "$f" 2>/dev/null ||
    printf '1\tVALIDATOR_CRASHED\t%s\n' "$f"
done)
echo "validate_gltf: ${#files[@]} files, ${#disagree[@]} disagreements"
for d in "${disagree[@]}"; do echo "  $d"; done
[ "$refused_valid" -eq 0 ]
