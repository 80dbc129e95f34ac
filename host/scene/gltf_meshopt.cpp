#include "scene/gltf_meshopt.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <meshoptimizer.h>

#include "scene/gltf_accessor.h"

namespace hrpp {
namespace {

// A compressed view decodes to at most this many times its compressed size (plus a little):
// meshopt's codecs reach ~64:1 on constant data; a larger claim is a corrupt or hostile file.
constexpr std::size_t kMaxRatio = 256, kMaxSlack = 1 << 16;

struct MeshoptView {
  int buffer = -1;
  std::size_t offset = 0, length = 0, stride = 0, count = 0;
  std::string mode, filter = "NONE";
};

int int_member(const tinygltf::Value& ext, const char* key, int fallback) {
  if (!ext.Has(key)) return fallback;
  const tinygltf::Value& v = ext.Get(key);
  return v.IsNumber() ? v.GetNumberAsInt() : -1;
}

MeshoptView parse(const tinygltf::Value& ext, const std::string& where) {
  if (!ext.IsObject()) throw GltfError(where + " is not an object");
  const int buffer = int_member(ext, "buffer", -1), offset = int_member(ext, "byteOffset", 0),
            length = int_member(ext, "byteLength", -1), stride = int_member(ext, "byteStride", -1),
            count = int_member(ext, "count", -1);
  if (buffer < 0 || offset < 0 || length < 0 || stride <= 0 || count < 0) {
    throw GltfError(where +
                    ": buffer, byteOffset, byteLength, byteStride or count missing or "
                    "out of range");
  }
  MeshoptView v;
  v.buffer = buffer;
  v.offset = static_cast<std::size_t>(offset);
  v.length = static_cast<std::size_t>(length);
  v.stride = static_cast<std::size_t>(stride);
  v.count = static_cast<std::size_t>(count);
  if (ext.Has("mode") && ext.Get("mode").IsString()) v.mode = ext.Get("mode").Get<std::string>();
  if (ext.Has("filter") && ext.Get("filter").IsString()) {
    v.filter = ext.Get("filter").Get<std::string>();
  }
  return v;
}

// The codec's and the filter's own preconditions (meshoptimizer asserts them, unchecked in
// release builds): the empty string when they hold, else what is wrong.
std::string check(const MeshoptView& v) {
  const bool index_stride = v.stride == 2 || v.stride == 4;
  if (v.mode == "ATTRIBUTES") {
    if (v.stride % 4 != 0 || v.stride > 256) return "ATTRIBUTES byteStride must be 4..256, x4";
  } else if (v.mode == "TRIANGLES") {
    if (!index_stride || v.count % 3 != 0) return "TRIANGLES needs byteStride 2 or 4, count x3";
  } else if (v.mode == "INDICES") {
    if (!index_stride) return "INDICES needs byteStride 2 or 4";
  } else {
    return "unknown mode \"" + v.mode + "\"";
  }
  if (v.filter == "NONE") return "";
  if (v.mode != "ATTRIBUTES") return "filter " + v.filter + " on " + v.mode;
  if (v.filter == "OCTAHEDRAL" && v.stride != 4 && v.stride != 8) return "OCTAHEDRAL stride";
  if (v.filter == "QUATERNION" && v.stride != 8) return "QUATERNION needs byteStride 8";
  if (v.filter == "OCTAHEDRAL" || v.filter == "QUATERNION" || v.filter == "EXPONENTIAL") {
    return "";
  }
  return "unknown filter \"" + v.filter + "\"";
}

std::vector<std::uint8_t> decode(const MeshoptView& v, const std::uint8_t* src,
                                 const std::string& where) {
  std::vector<std::uint8_t> out(v.count * v.stride);
  int rc = 0;
  if (v.mode == "ATTRIBUTES") {
    rc = meshopt_decodeVertexBuffer(out.data(), v.count, v.stride, src, v.length);
  } else if (v.mode == "TRIANGLES") {
    rc = meshopt_decodeIndexBuffer(out.data(), v.count, v.stride, src, v.length);
  } else {
    rc = meshopt_decodeIndexSequence(out.data(), v.count, v.stride, src, v.length);
  }
  if (rc != 0)
    throw GltfError(where + ": corrupt " + v.mode + " data (meshopt error " + std::to_string(rc) +
                    ")");
  if (v.filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out.data(), v.count, v.stride);
  if (v.filter == "QUATERNION") meshopt_decodeFilterQuat(out.data(), v.count, v.stride);
  if (v.filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data(), v.count, v.stride);
  return out;
}

void decode_view(tinygltf::Model& model, int index, const tinygltf::Value& ext) {
  const std::string where = "bufferView " + std::to_string(index) + " (EXT_meshopt_compression)";
  const MeshoptView v = parse(ext, where);
  const std::string problem = check(v);
  if (!problem.empty()) throw GltfError(where + ": " + problem);
  if (static_cast<std::size_t>(v.buffer) >= model.buffers.size()) {
    throw GltfError(where + ": buffer " + std::to_string(v.buffer) + " does not exist");
  }
  const std::vector<unsigned char>& data = model.buffers[v.buffer].data;
  std::size_t end = 0;
  if (__builtin_add_overflow(v.offset, v.length, &end) || end > data.size()) {
    throw GltfError(where + ": compressed bytes lie past the end of buffer " +
                    std::to_string(v.buffer));
  }
  std::size_t decoded = 0;
  if (__builtin_mul_overflow(v.count, v.stride, &decoded) ||
      decoded > kMaxRatio * v.length + kMaxSlack) {
    throw GltfError(where + ": " + std::to_string(v.count) + " elements of " +
                    std::to_string(v.stride) + " bytes cannot come from " +
                    std::to_string(v.length) + " compressed bytes");
  }
  tinygltf::Buffer out;
  out.data = decode(v, data.data() + v.offset, where);
  model.buffers.push_back(std::move(out));
  tinygltf::BufferView& bv = model.bufferViews[index];
  bv.buffer = static_cast<int>(model.buffers.size() - 1);
  bv.byteOffset = 0;
  bv.byteLength = decoded;
  if (v.mode == "ATTRIBUTES") bv.byteStride = v.stride;
}

}  // namespace

void decode_meshopt_views(tinygltf::Model& model) {
  for (std::size_t i = 0; i < model.bufferViews.size(); ++i) {
    const tinygltf::ExtensionMap& ext = model.bufferViews[i].extensions;
    auto it = ext.find("EXT_meshopt_compression");
    if (it != ext.end()) decode_view(model, static_cast<int>(i), tinygltf::Value(it->second));
  }
}

}  // namespace hrpp
