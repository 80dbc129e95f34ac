#include "scene/gltf_draco.h"

#include <cstdint>
#include <cstring>
#include <memory>
#include <string>

#include <draco/compression/decode.h>

#include "scene/gltf_accessor.h"

namespace hrpp {
namespace {

constexpr const char* kDraco = "KHR_draco_mesh_compression";

// Appends `bytes` as a new buffer and bufferView; points accessor `index` at it.
void attach(tinygltf::Model& model, int index, std::vector<std::uint8_t> bytes) {
  tinygltf::Buffer buffer;
  buffer.data = std::move(bytes);
  tinygltf::BufferView bv;
  bv.buffer = static_cast<int>(model.buffers.size());
  bv.byteLength = buffer.data.size();
  model.buffers.push_back(std::move(buffer));
  model.bufferViews.push_back(bv);
  tinygltf::Accessor& acc = model.accessors[index];
  acc.bufferView = static_cast<int>(model.bufferViews.size() - 1);
  acc.byteOffset = 0;
}

template <typename T>
std::vector<std::uint8_t> convert(const draco::Mesh& mesh, const draco::PointAttribute& att,
                                  int components, const std::string& where) {
  const std::size_t n = mesh.num_points();
  std::vector<std::uint8_t> out(n * components * sizeof(T));
  std::vector<T> value(components);
  for (std::size_t i = 0; i < n; ++i) {
    const draco::AttributeValueIndex v =
        att.mapped_index(draco::PointIndex(static_cast<std::uint32_t>(i)));
    if (!att.ConvertValue<T>(v, static_cast<std::int8_t>(components), value.data())) {
      throw GltfError(where + ": Draco attribute cannot be converted");
    }
    std::memcpy(&out[i * components * sizeof(T)], value.data(), components * sizeof(T));
  }
  return out;
}

std::vector<std::uint8_t> attribute_bytes(const draco::Mesh& mesh, const draco::PointAttribute& att,
                                          const tinygltf::Accessor& acc, const std::string& where) {
  const int components = gltf_type_components(acc.type);
  if (components < 1 || components > 4 || components != att.num_components()) {
    throw GltfError(where + ": the accessor's type does not match the Draco attribute (" +
                    std::to_string(att.num_components()) + " components)");
  }
  switch (acc.componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return convert<float>(mesh, att, components, where);
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return convert<std::int8_t>(mesh, att, components, where);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return convert<std::uint8_t>(mesh, att, components, where);
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return convert<std::int16_t>(mesh, att, components, where);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return convert<std::uint16_t>(mesh, att, components, where);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return convert<std::uint32_t>(mesh, att, components, where);
    default:
      throw GltfError(where + ": invalid componentType " + std::to_string(acc.componentType));
  }
}

std::unique_ptr<draco::Mesh> decode_mesh(const tinygltf::Model& model, const tinygltf::Value& ext,
                                         const std::string& where) {
  if (!ext.IsObject() || !ext.Has("bufferView") || !ext.Get("bufferView").IsNumber()) {
    throw GltfError(where + ": no bufferView");
  }
  std::size_t size = 0;
  const std::uint8_t* bytes =
      AccessorReader(model).view_bytes(ext.Get("bufferView").GetNumberAsInt(), size);
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes), size);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) throw GltfError(where + ": " + decoded.status().error_msg_string());
  std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  if (!mesh) throw GltfError(where + ": no mesh decoded");
  return mesh;
}

void decode_indices(tinygltf::Model& model, const draco::Mesh& mesh, int accessor,
                    const std::string& where) {
  if (accessor < 0 || static_cast<std::size_t>(accessor) >= model.accessors.size()) {
    throw GltfError(where + ": indices accessor " + std::to_string(accessor) + " does not exist");
  }
  const std::size_t n = static_cast<std::size_t>(mesh.num_faces()) * 3;
  if (model.accessors[accessor].count != n) {
    throw GltfError(where + ": accessor " + std::to_string(accessor) + " has " +
                    std::to_string(model.accessors[accessor].count) + " indices, Draco decoded " +
                    std::to_string(n));
  }
  std::vector<std::uint8_t> bytes(n * 4);
  for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.face(f)[k].value();
      std::memcpy(&bytes[(3 * f.value() + k) * 4], &v, 4);
    }
  }
  model.accessors[accessor].componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  attach(model, accessor, std::move(bytes));
}

void decode_attributes(tinygltf::Model& model, const draco::Mesh& mesh,
                       const tinygltf::Primitive& prim, const tinygltf::Value& ext,
                       const std::string& where) {
  if (!ext.Has("attributes") || !ext.Get("attributes").IsObject()) {
    throw GltfError(where + ": no attributes");
  }
  const tinygltf::Value& map = ext.Get("attributes");
  for (const std::string& name : map.Keys()) {
    const std::string at = where + " " + name;
    auto it = prim.attributes.find(name);
    const tinygltf::Value& id = map.Get(name);
    if (it == prim.attributes.end() || !id.IsNumber() || id.GetNumberAsInt() < 0) {
      throw GltfError(at + ": not an attribute of the primitive, or no Draco attribute id");
    }
    const draco::PointAttribute* att =
        mesh.GetAttributeByUniqueId(static_cast<std::uint32_t>(id.GetNumberAsInt()));
    if (att == nullptr)
      throw GltfError(at + ": Draco attribute " + std::to_string(id.GetNumberAsInt()) +
                      " does not exist");
    if (it->second < 0 || static_cast<std::size_t>(it->second) >= model.accessors.size()) {
      throw GltfError(at + ": accessor " + std::to_string(it->second) + " does not exist");
    }
    const tinygltf::Accessor& acc = model.accessors[it->second];
    if (acc.count != mesh.num_points()) {
      throw GltfError(at + ": accessor " + std::to_string(it->second) + " has " +
                      std::to_string(acc.count) + " elements, Draco decoded " +
                      std::to_string(mesh.num_points()));
    }
    attach(model, it->second, attribute_bytes(mesh, *att, acc, at));
  }
}

}  // namespace

void decode_draco_primitives(tinygltf::Model& model, const std::vector<DracoIndices>& taken) {
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    for (std::size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
      tinygltf::Primitive& prim = model.meshes[m].primitives[p];
      auto ext = prim.extensions.find(kDraco);
      if (ext == prim.extensions.end()) continue;
      const std::string where =
          "mesh " + std::to_string(m) + " primitive " + std::to_string(p) + " (" + kDraco + ")";
      const std::unique_ptr<draco::Mesh> mesh = decode_mesh(model, ext->second, where);
      for (const DracoIndices& d : taken) {
        if (d.mesh != static_cast<int>(m) || d.primitive != static_cast<int>(p)) continue;
        decode_indices(model, *mesh, d.accessor, where);
        prim.indices = d.accessor;
      }
      decode_attributes(model, *mesh, prim, ext->second, where);
    }
  }
}

}  // namespace hrpp
