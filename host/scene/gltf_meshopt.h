// EXT_meshopt_compression: bufferViews whose bytes are stored meshoptimizer-compressed in another
// buffer (the extension's buffer/byteOffset/byteLength), decoded with libmeshoptimizer
// (meshopt_decodeVertexBuffer / IndexBuffer / IndexSequence, then the OCTAHEDRAL, QUATERNION or
// EXPONENTIAL filter in place).
#pragma once

#include <tiny_gltf.h>

namespace hrpp {

// Decodes every compressed bufferView of `model` into a new buffer of its own and points the
// view at it (byteOffset 0, byteLength the decoded size), so accessors read plain bytes. The
// fallback buffers those views named are left as they are (the pre-pass empties them: see
// gltf_prepass.h). Throws GltfError naming the bufferView on malformed or corrupt data.
void decode_meshopt_views(tinygltf::Model& model);

}  // namespace hrpp
