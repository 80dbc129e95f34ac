#!/usr/bin/env bash
# Regenerates tests/data/gltf_encodings/: one mesh (the Utah teapot, scenes/meshes/utah_teapot.glb,
# 992 triangles, normals generated) in each encoding the glTF loader reads, as the optimisers
# users run write them. tests/gltf_encodings_test.cpp checks that each flattens to the plain
# file's triangles within the quantization step; the tests read the committed files and never
# need npm. This script does: it installs pinned gltfpack and glTF-Transform from the npm
# registry into a scratch directory (NPM_TOOLS, default /tmp/hrpp-npm-tools), not the repository.
#
#   plain.glb                 FLOAT positions and normals, no extension (the reference)
#   quantized_gltfpack.glb    KHR_mesh_quantization: UNSIGNED_SHORT positions + node transform,
#                             normalized BYTE normals (gltfpack's defaults)
#   quantized_transform.glb   KHR_mesh_quantization: normalized SHORT positions and normals
#                             (glTF-Transform quantize)
#   meshopt_gltfpack.glb      EXT_meshopt_compression over quantized data, OCTAHEDRAL normals
#   meshopt_float.glb         EXT_meshopt_compression over FLOAT data, EXPONENTIAL filter
#   meshopt_transform.gltf    EXT_meshopt_compression (glTF-Transform), .gltf + .bin
#   draco.glb                 KHR_draco_mesh_compression (glTF-Transform draco)
#
# Usage: tests/gltf/make_encodings.sh
set -euo pipefail

root="$(cd "$(dirname "$0")/../.." && pwd)"
out="$root/tests/data/gltf_encodings"
tools="${NPM_TOOLS:-/tmp/hrpp-npm-tools}"
mkdir -p "$tools" "$out"
pack="$tools/node_modules/.bin/gltfpack"
transform="$tools/node_modules/.bin/gltf-transform"
if [ ! -x "$pack" ] || [ ! -x "$transform" ]; then
  (cd "$tools" && npm install --no-save --silent gltfpack@1.3.0 @gltf-transform/cli@4.5.1)
fi

rm -f "$out"/*.glb "$out"/*.gltf "$out"/*.bin
"$pack" -i "$root/scenes/meshes/utah_teapot.glb" -o "$out/plain.glb" -noq -gn 60 >/dev/null
"$pack" -i "$out/plain.glb" -o "$out/quantized_gltfpack.glb" >/dev/null
"$pack" -i "$out/plain.glb" -o "$out/meshopt_gltfpack.glb" -cc >/dev/null
"$pack" -i "$out/plain.glb" -o "$out/meshopt_float.glb" -cc -vpf -vnf >/dev/null
"$transform" quantize "$out/plain.glb" "$out/quantized_transform.glb" >/dev/null
"$transform" meshopt "$out/plain.glb" "$out/meshopt_transform.gltf" >/dev/null
"$transform" draco "$out/plain.glb" "$out/draco.glb" >/dev/null
ls -l "$out"
