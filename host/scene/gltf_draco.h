// KHR_draco_mesh_compression: primitives whose attributes and indices are one Draco-compressed
// bufferView, decoded with libdraco into plain buffers the rest of the loader reads.
#pragma once

#include <vector>

#include <tiny_gltf.h>

#include "scene/gltf_prepass.h"

namespace hrpp {

// Decodes every Draco primitive of `model`: its indices (the accessors the pre-pass took out,
// `taken`, put back as UNSIGNED_INT) and the attributes the extension maps, each into a new
// buffer and bufferView that its accessor then names, in the accessor's component type. Throws
// GltfError naming the mesh and primitive on malformed or corrupt data.
void decode_draco_primitives(tinygltf::Model& model, const std::vector<DracoIndices>& taken);

}  // namespace hrpp
