// A look at a glTF file's JSON before tinygltf parses it:
//  - extensionsRequired naming an extension the loader cannot honour is refused (one line naming
//    the extension); extensions only in extensionsUsed that it does not know are ignored with a
//    warning;
//  - compressed files are made parseable by tinygltf 2.7 (Debian 12), which knows neither
//    extension: EXT_meshopt_compression's fallback buffers (no data, byteLength of the decoded
//    bytes) get a 3-byte placeholder, and KHR_draco_mesh_compression primitives lose their
//    "indices" (an accessor without a bufferView, which tinygltf refuses) until the Draco
//    decoder gives them one (gltf_draco.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hrpp {

// The extensions the loader reads, in the order the docs list them.
const std::vector<std::string>& supported_gltf_extensions();

// A Draco primitive's indices accessor, taken out of the JSON by the pre-pass.
struct DracoIndices {
  int mesh = 0, primitive = 0, accessor = -1;
};

struct GltfPrepass {
  std::vector<std::string> warnings;
  std::vector<DracoIndices> draco_indices;
  bool changed = false;  // `json` holds the JSON to parse instead of the file's
  std::string json;
};

// Inspects (and, for compressed files, rewrites) the JSON text. Text that is not a JSON object
// is left to tinygltf, whose messages say what is wrong. Throws GltfError for a required
// extension that is not supported.
GltfPrepass gltf_prepass(const std::uint8_t* json, std::size_t size);

// The file's bytes with its JSON replaced: a GLB gets a new JSON chunk (the chunks after it
// kept, from json_end: where the file's JSON chunk ends), a .gltf is the JSON itself.
std::vector<std::uint8_t> replace_json(const std::vector<std::uint8_t>& bytes, bool glb,
                                       std::size_t json_end, const std::string& json);

}  // namespace hrpp
