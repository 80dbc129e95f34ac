#include "scene/gltf_prepass.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "scene/gltf_accessor.h"

namespace hrpp {
namespace {

using nlohmann::json;

constexpr const char* kMeshopt = "EXT_meshopt_compression";
constexpr const char* kDraco = "KHR_draco_mesh_compression";

bool supported(const std::string& name) {
  const auto& all = supported_gltf_extensions();
  return std::find(all.begin(), all.end(), name) != all.end();
}

std::vector<std::string> names(const json& doc, const char* key) {
  std::vector<std::string> out;
  if (!doc.contains(key) || !doc[key].is_array()) return out;
  for (const json& e : doc[key]) {
    if (e.is_string()) out.push_back(e.get<std::string>());
  }
  return out;
}

void check_extensions(const json& doc, GltfPrepass& out) {
  for (const std::string& e : names(doc, "extensionsRequired")) {
    if (!supported(e)) {
      throw GltfError("extension " + e + " is required by the file but not supported");
    }
  }
  std::string ignored;
  for (const std::string& e : names(doc, "extensionsUsed")) {
    if (!supported(e)) ignored += (ignored.empty() ? "" : ", ") + e;
  }
  if (!ignored.empty()) out.warnings.push_back("extensions not supported, ignored: " + ignored);
}

bool has_extension(const json& object, const char* name) {
  return object.is_object() && object.contains("extensions") && object["extensions"].is_object() &&
         object["extensions"].contains(name);
}

// Fallback buffers without data: a 3-byte placeholder (decode_meshopt_views never reads it).
bool patch_meshopt(json& doc) {
  bool changed = false;
  if (!doc.contains("buffers") || !doc["buffers"].is_array()) return false;
  for (json& buffer : doc["buffers"]) {
    if (!has_extension(buffer, kMeshopt) || buffer.contains("uri")) continue;
    buffer["uri"] = "data:application/octet-stream;base64,AAAA";
    buffer["byteLength"] = 3;
    changed = true;
  }
  return changed;
}

bool patch_draco(json& doc, GltfPrepass& out) {
  if (!doc.contains("meshes") || !doc["meshes"].is_array()) return false;
  bool changed = false;
  for (std::size_t m = 0; m < doc["meshes"].size(); ++m) {
    json& mesh = doc["meshes"][m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) {
      continue;
    }
    for (std::size_t p = 0; p < mesh["primitives"].size(); ++p) {
      json& prim = mesh["primitives"][p];
      if (!has_extension(prim, kDraco) || !prim.contains("indices")) continue;
      if (!prim["indices"].is_number_integer()) continue;  // tinygltf reports it
      out.draco_indices.push_back(
          {static_cast<int>(m), static_cast<int>(p), prim["indices"].get<int>()});
      prim.erase("indices");
      changed = true;
    }
  }
  return changed;
}

}  // namespace

const std::vector<std::string>& supported_gltf_extensions() {
  static const std::vector<std::string> kAll = {
      "KHR_mesh_quantization",           "EXT_meshopt_compression",
      "KHR_draco_mesh_compression",      "KHR_texture_transform",
      "KHR_materials_emissive_strength", "KHR_materials_ior",
      "KHR_materials_transmission",      "KHR_lights_punctual"};
  return kAll;
}

GltfPrepass gltf_prepass(const std::uint8_t* text, std::size_t size) {
  GltfPrepass out;
  json doc = json::parse(text, text + size, nullptr, /*allow_exceptions=*/false);
  if (!doc.is_object()) return out;
  check_extensions(doc, out);
  const bool meshopt = patch_meshopt(doc);
  const bool draco = patch_draco(doc, out);
  if (meshopt || draco) {
    out.changed = true;
    out.json = doc.dump();
  }
  return out;
}

std::vector<std::uint8_t> replace_json(const std::vector<std::uint8_t>& bytes, bool glb,
                                       std::size_t json_end, const std::string& text) {
  if (!glb) return std::vector<std::uint8_t>(text.begin(), text.end());
  std::string padded = text;
  padded.resize((padded.size() + 3) / 4 * 4, ' ');
  const std::size_t rest = std::min(bytes.size(), json_end);
  std::vector<std::uint8_t> out;
  out.reserve(20 + padded.size() + bytes.size() - rest);
  const auto put = [&](std::uint32_t v) {
    for (int b = 0; b < 4; ++b) out.push_back(static_cast<std::uint8_t>(v >> (8 * b)));
  };
  const auto put_text = [&](const std::string& t) { out.insert(out.end(), t.begin(), t.end()); };
  put_text("glTF");
  put(2);
  put(static_cast<std::uint32_t>(20 + padded.size() + (bytes.size() - rest)));
  put(static_cast<std::uint32_t>(padded.size()));
  put_text("JSON");
  put_text(padded);
  out.insert(out.end(), bytes.begin() + static_cast<std::ptrdiff_t>(rest), bytes.end());
  return out;
}

}  // namespace hrpp
