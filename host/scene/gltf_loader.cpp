// glTF 2.0 loader (.gltf / .glb) on top of tinygltf. tinygltf parses the JSON and the buffers; this
// file validates everything it reads itself (indices, byte ranges, component types, node graph,
// finite positions) and flattens the default scene into world-space triangles in triangle-id
// order (docs/FORMATS.md): root nodes in listed order, each node depth-first (its own mesh,
// then its children), primitives in order, triangles in index order.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <tiny_gltf.h>

#include "common/error.h"
#include "scene/gltf_accessor.h"
#include "scene/gltf_draco.h"
#include "scene/gltf_meshopt.h"
#include "scene/gltf_prepass.h"
#include "scene/gltf_topology.h"
#include "scene/texture_decode.h"
#include "scene/load_scene.h"

namespace hrpp {
namespace {

// Limits on what one file may expand to: a few hundred bytes of JSON can instance a mesh 2^40
// times through a node graph that reuses nodes (a DAG), or name a file of any size as a buffer.
constexpr std::size_t kMaxReusedNodes = std::size_t{1} << 16;  // node visits beyond node count
constexpr std::size_t kMaxTriangles = std::size_t{1} << 27;      // ~13 GiB of scene data
constexpr std::uintmax_t kMaxExternalFileBytes = (std::uintmax_t{1} << 32) - 1;
constexpr std::size_t kMaxJsonDepth = 512;  // real files nest < 10 levels

// Deepest nesting of [ and { in a JSON text (outside strings); stops counting past the limit.
std::size_t json_nesting_depth(const unsigned char* text, std::size_t size) {
  std::size_t depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < size; ++i) {
    const unsigned char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
      if (deepest > kMaxJsonDepth) break;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

// tinygltf messages are multi-line; errors are one line.
std::string one_line(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    if (c == ' ' && (out.empty() || out.back() == ' ')) continue;
    out.push_back(c);
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// Image loader hook: decode nothing while tinygltf parses. Images referenced by URI keep their
// raw bytes (as_is); images in buffer views are decoded later from a range validated here (tinygltf
// does not check that range). Only images actually used as base colour textures get decoded.
bool defer_image(tinygltf::Image* image, const int /*image_idx*/, std::string* /*err*/,
                 std::string* /*warn*/, int /*req_width*/, int /*req_height*/,
                 const unsigned char* bytes, int size, void* /*user_data*/) {
  if (image->bufferView < 0 && bytes != nullptr && size > 0) {
    image->image.assign(bytes, bytes + size);
    image->as_is = true;
  }
  return true;
}

// tinygltf's file reader, made safe for any URI: only regular files (a directory, /dev/zero or
// a FIFO would throw std::bad_alloc or block), at most kMaxExternalFileBytes.
bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                     void* /*user_data*/) {
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  std::string problem;
  if (ec || !std::filesystem::exists(st)) {
    problem = "not found";
  } else if (!std::filesystem::is_regular_file(st)) {
    problem = "is not a regular file";
  } else {
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) {
      problem = "cannot be read: " + ec.message();
    } else if (size > kMaxExternalFileBytes) {
      problem = "is 4 GiB or larger";
    } else {
      std::FILE* f = std::fopen(path.c_str(), "rb");
      if (f == nullptr) {
        problem = "cannot be opened";
      } else {
        out->resize(static_cast<std::size_t>(size));
        const bool ok = std::fread(out->data(), 1, out->size(), f) == out->size();
        std::fclose(f);
        if (!ok) problem = "cannot be read";
      }
    }
  }
  if (problem.empty()) return true;
  if (err != nullptr) *err += "file " + path + " " + problem;
  return false;
}

glm::dmat4 node_local_matrix(const tinygltf::Node& node) {
  if (!node.matrix.empty()) return glm::make_mat4(node.matrix.data());  // column-major
  glm::dmat4 m(1.0);
  if (!node.translation.empty()) {
    m[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
  }
  if (!node.rotation.empty()) {
    // glTF stores quaternions as x, y, z, w; glm's constructor takes w first.
    const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    m = m * glm::mat4_cast(glm::normalize(q));
  }
  if (!node.scale.empty()) {
    m = m * glm::dmat4(glm::dvec4(node.scale[0], 0, 0, 0), glm::dvec4(0, node.scale[1], 0, 0),
                       glm::dvec4(0, 0, node.scale[2], 0), glm::dvec4(0, 0, 0, 1));
  }
  return m;
}

glm::vec3 to_vec3(const std::vector<double>& v, glm::vec3 fallback) {
  if (v.size() < 3) return fallback;
  return glm::vec3(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
}

// The formats a vertex attribute may have: FLOAT, or with KHR_mesh_quantization the small
// integer types in `integers` (bits: 1 << (componentType - BYTE)), normalized or not (or only
// normalized: normalized_only); COLOR_0 may be VEC3 or VEC4.
struct AttributeFormat {
  const char* semantic;
  int type, other_type = 0;  // other_type: 0, or a second type allowed
  unsigned integers = 0;
  bool normalized_only = false;
  const char* expected = "";
};
constexpr unsigned kSmallInts = 0b1111, kSignedInts = 0b0101, kUnsignedInts = 0b1010;
constexpr AttributeFormat kPosition = {
    .semantic = "POSITION",
    .type = TINYGLTF_TYPE_VEC3,
    .integers = kSmallInts,
    .expected = "FLOAT VEC3 or (normalized) BYTE/UNSIGNED_BYTE/SHORT/UNSIGNED_SHORT VEC3"};
constexpr AttributeFormat kNormal = {.semantic = "NORMAL",
                                     .type = TINYGLTF_TYPE_VEC3,
                                     .integers = kSignedInts,
                                     .normalized_only = true,
                                     .expected = "FLOAT VEC3 or normalized BYTE/SHORT VEC3"};
constexpr AttributeFormat kTexcoord = {
    .semantic = "TEXCOORD_0",
    .type = TINYGLTF_TYPE_VEC2,
    .integers = kSmallInts,
    .expected = "FLOAT VEC2 or (normalized) BYTE/UNSIGNED_BYTE/SHORT/UNSIGNED_SHORT VEC2"};
constexpr AttributeFormat kColor = {
    .semantic = "COLOR_0",
    .type = TINYGLTF_TYPE_VEC3,
    .other_type = TINYGLTF_TYPE_VEC4,
    .integers = kUnsignedInts,
    .normalized_only = true,
    .expected = "FLOAT VEC3/VEC4 or normalized UNSIGNED_BYTE/UNSIGNED_SHORT VEC3/VEC4"};

class GltfLoader {
 public:
  GltfLoader(const tinygltf::Model& model, std::string file, Scene& scene)
      : m_(model), file_(std::move(file)), scene_(scene) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(one_line(file_ + ": " + what));
  }

  void load() {
    try {
      load_default_scene();
    } catch (const GltfError& e) {
      fail(e.what());
    }
  }

 private:
  void load_default_scene() {
    if (m_.scenes.empty()) fail("glTF has no scene");
    int scene_index = m_.defaultScene;
    if (scene_index < 0) scene_index = 0;
    if (static_cast<std::size_t>(scene_index) >= m_.scenes.size()) {
      fail("default scene " + std::to_string(scene_index) + " does not exist");
    }
    convert_materials();
    texture_of_image_.assign(m_.images.size(), -1);
    state_.assign(m_.nodes.size(), 0);
    for (int root : m_.scenes[scene_index].nodes) walk(root, glm::dmat4(1.0));
    report_skipped();
    if (!ragged_.empty()) {
      warn(std::to_string(ragged_.size()) + " TRIANGLES primitive" +
           (ragged_.size() == 1 ? "" : "s") +
           " with a vertex or index count not a multiple of 3: the last 1 or 2 ignored");
    }
    if (texcoord_override_) warn("KHR_texture_transform texCoord ignored (TEXCOORD_0 is used)");
  }

  void warn(const std::string& what) { scene_.warnings.push_back(one_line(file_ + ": " + what)); }

  // Points and lines are valid glTF but no surface: skipped with one warning, or refused when
  // nothing else is left.
  void report_skipped() {
    if (skipped_.empty()) return;
    const std::string what = std::to_string(skipped_.size()) + " points/lines primitive" +
                             (skipped_.size() == 1 ? "" : "s");
    if (scene_.triangles.empty()) fail("no triangles: only " + what + " (not surfaces)");
    warn(what + " skipped (not surfaces)");
  }

  // ---- materials -----------------------------------------------------------------------------
  static double ext_number(const tinygltf::ExtensionMap& ext, const char* name, const char* key,
                           double fallback) {
    auto it = ext.find(name);
    if (it == ext.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
    const tinygltf::Value& v = it->second.Get(key);
    return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
  }

  // An extension's RGB factor (NaN in a channel that is not a number, for the finite check).
  static glm::vec3 ext_rgb(const tinygltf::ExtensionMap& ext, const char* name, const char* key,
                           glm::vec3 fallback) {
    auto it = ext.find(name);
    if (it == ext.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
    const tinygltf::Value& a = it->second.Get(key);
    glm::vec3 v(NAN);
    for (int c = 0; c < 3; ++c) {
      if (a.IsArray() && a.ArrayLen() == 3 && a.Get(c).IsNumber())
        v[c] = static_cast<float>(a.Get(c).GetNumberAsDouble());
    }
    return v;
  }

  void convert_materials() {
    for (std::size_t i = 0; i < m_.materials.size(); ++i) {
      const tinygltf::Material& gm = m_.materials[i];
      const auto& pbr = gm.pbrMetallicRoughness;
      Material mat;
      mat.name = gm.name.empty() ? "material " + std::to_string(i) : gm.name;
      mat.base_color = to_vec3(pbr.baseColorFactor, glm::vec3(1.0f));
      mat.metallic = static_cast<float>(pbr.metallicFactor);
      mat.roughness = static_cast<float>(pbr.roughnessFactor);
      const double strength =
          ext_number(gm.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
      mat.emission = to_vec3(gm.emissiveFactor, glm::vec3(0.0f)) * static_cast<float>(strength);
      mat.ior = static_cast<float>(ext_number(gm.extensions, "KHR_materials_ior", "ior", 1.5));
      mat.transmission = static_cast<float>(
          ext_number(gm.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0));
      mat.specular = static_cast<float>(
          ext_number(gm.extensions, "KHR_materials_specular", "specularFactor", 1.0));
      mat.specular_color = ext_rgb(gm.extensions, "KHR_materials_specular", "specularColorFactor",
                                   glm::vec3(1.0f));
      const glm::vec3 checks[] = {mat.base_color, mat.emission,
                                  glm::vec3(mat.metallic, mat.roughness, mat.ior),
                                  glm::vec3(mat.transmission, mat.specular, 0.0f),
                                  mat.specular_color};
      for (const glm::vec3& c : checks) {
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) {
          fail("material " + std::to_string(i) + " has a non-finite factor");
        }
      }
      scene_.materials.push_back(std::move(mat));
      // Texture decoding is deferred until first use (see walk), but resolved here for errors.
      slots_.push_back({pbr.baseColorTexture.index, pbr.metallicRoughnessTexture.index,
                        gm.emissiveTexture.index});
      uv_transform_.push_back(material_transform(gm, i));
    }
  }

  // The KHR_texture_transform of material i's texcoords. Vertices carry one set, so its textures
  // share the first one's transform (base colour, metallic-roughness, emissive); another slot's
  // different transform is warned about.
  std::optional<glm::mat3> material_transform(const tinygltf::Material& gm, std::size_t i) {
    const auto& pbr = gm.pbrMetallicRoughness;
    const struct {
      int index;
      const tinygltf::ExtensionMap& ext;
      const char* name;
    } slots[] = {{pbr.baseColorTexture.index, pbr.baseColorTexture.extensions, "baseColorTexture"},
                 {pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.extensions,
                  "metallicRoughnessTexture"},
                 {gm.emissiveTexture.index, gm.emissiveTexture.extensions, "emissiveTexture"}};
    std::optional<glm::mat3> chosen;
    const char* chosen_name = nullptr;
    for (const auto& slot : slots) {
      if (slot.index < 0) continue;
      const std::optional<glm::mat3> t = texture_transform(slot.ext, i);
      if (!chosen_name) {
        chosen = t;
        chosen_name = slot.name;
      } else if (t != chosen) {
        warn("material " + std::to_string(i) + ": the " + slot.name +
             "'s KHR_texture_transform differs from the " + chosen_name + "'s, which is used");
      }
    }
    return chosen;
  }

  // KHR_texture_transform of a material's base colour texture as the matrix the spec gives:
  // translation(offset) * rotation(rotation) * scale(scale), applied to (u, v, 1).
  std::optional<glm::mat3> texture_transform(const tinygltf::ExtensionMap& ext, std::size_t i) {
    auto it = ext.find("KHR_texture_transform");
    if (it == ext.end() || !it->second.IsObject()) return std::nullopt;
    auto pair = [&](const char* key, float fallback) {
      glm::vec2 v(fallback);
      if (!it->second.Has(key)) return v;
      const tinygltf::Value& a = it->second.Get(key);
      for (int c = 0; c < 2; ++c) {
        const bool ok = a.IsArray() && a.ArrayLen() == 2 && a.Get(c).IsNumber();
        v[c] = ok ? static_cast<float>(a.Get(c).GetNumberAsDouble()) : NAN;
      }
      return v;
    };
    const glm::vec2 offset = pair("offset", 0.0f), scale = pair("scale", 1.0f);
    const float r = static_cast<float>(ext_number(ext, "KHR_texture_transform", "rotation", 0.0));
    if (!std::isfinite(offset.x + offset.y + scale.x + scale.y + r)) {
      fail("material " + std::to_string(i) +
           ": KHR_texture_transform has a non-numeric or "
           "non-finite offset, rotation or scale");
    }
    if (it->second.Has("texCoord")) texcoord_override_ = true;
    const float c = std::cos(r), s = std::sin(r);
    // Columns (as the extension's GLSL, column-major): the images of u, v and 1.
    return glm::mat3(glm::vec3(c * scale.x, s * scale.x, 0.0f),
                     glm::vec3(-s * scale.y, c * scale.y, 0.0f), glm::vec3(offset, 1.0f));
  }

  void transform_texcoords(int material, std::vector<glm::vec2>& uv) const {
    const std::optional<glm::mat3>& t = uv_transform_[material];
    if (!t) return;
    for (glm::vec2& p : uv) p = glm::vec2(*t * glm::vec3(p, 1.0f));
  }

  // The scene's texture for glTF texture `tex` of material material_index's slot (-1: none).
  int texture_for(int material_index, int tex, const char* slot) {
    if (tex < 0) return -1;
    const std::string where = "material " + std::to_string(material_index) + " " + slot;
    if (static_cast<std::size_t>(tex) >= m_.textures.size()) {
      fail(where + ": texture " + std::to_string(tex) + " does not exist");
    }
    const int img = m_.textures[tex].source;
    if (img < 0) return -1;  // e.g. only an extension source (KTX2, WebP): not supported, untextured
    if (static_cast<std::size_t>(img) >= m_.images.size()) {
      fail("texture " + std::to_string(tex) + ": image " + std::to_string(img) +
           " does not exist");
    }
    if (texture_of_image_[img] >= 0) return texture_of_image_[img];
    texture_of_image_[img] = decode_image(img);
    return texture_of_image_[img];
  }

  int decode_image(int img) {
    const tinygltf::Image& gi = m_.images[img];
    const std::uint8_t* bytes = nullptr;
    std::size_t size = 0;
    if (gi.bufferView >= 0) {
      bytes = reader_.view_bytes(gi.bufferView, size);
    } else if (gi.as_is) {
      bytes = gi.image.data();
      size = gi.image.size();
    } else if (!gi.uri.empty() && gi.uri.rfind("data:", 0) != 0) {
      fail("image " + std::to_string(img) + ": file " + gi.uri + " not found or unreadable");
    } else {
      fail("image " + std::to_string(img) + " has no data");
    }
    if (size == 0 || size > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
      fail("image " + std::to_string(img) + " has an invalid size");
    }
    const std::string name =
        gi.name.empty() ? (gi.uri.empty() ? "image " + std::to_string(img) : gi.uri) : gi.name;
    Texture tex =
        decode_texture({bytes, size}, name, one_line(file_ + ": image " + std::to_string(img)));
    scene_.textures.push_back(std::move(tex));
    return static_cast<int>(scene_.textures.size() - 1);
  }

  std::uint32_t material_for(int index, int mesh, int prim) {
    if (index < 0) {
      if (default_material_ < 0) {
        Material def;
        def.name = "default";
        scene_.materials.push_back(def);
        default_material_ = static_cast<int>(scene_.materials.size() - 1);
      }
      return static_cast<std::uint32_t>(default_material_);
    }
    if (static_cast<std::size_t>(index) >= m_.materials.size()) {
      fail("mesh " + std::to_string(mesh) + " primitive " + std::to_string(prim) +
           ": material " + std::to_string(index) + " does not exist");
    }
    if (!texture_resolved_.count(index)) {
      texture_resolved_.insert(index);
      const TextureSlots& t = slots_[index];
      Material& mat = scene_.materials[index];
      mat.base_color_texture = texture_for(index, t.base_color, "baseColorTexture");
      mat.metallic_roughness_texture =
          texture_for(index, t.metallic_roughness, "metallicRoughnessTexture");
      // emissiveFactor (default 0) scales the texture: without it, nothing emits.
      if (mat.emission != glm::vec3(0.0f))
        mat.emissive_texture = texture_for(index, t.emissive, "emissiveTexture");
    }
    return static_cast<std::uint32_t>(index);
  }

  // ---- node graph ----------------------------------------------------------------------------
  // Iterative depth-first walk (deep hierarchies must not overflow the call stack); state_ marks
  // nodes on the current path so that cycles are detected.
  void walk(int root, const glm::dmat4& parent) {
    struct Frame {
      int node;
      glm::dmat4 world;
      std::size_t next_child;
    };
    std::vector<Frame> stack;
    // from -1: a root of the scene.
    auto enter = [&](int node, const glm::dmat4& parent_world, int from) {
      if (node < 0 || static_cast<std::size_t>(node) >= m_.nodes.size()) {
        fail((from < 0 ? std::string("scene") : "node " + std::to_string(from)) + ": node " +
             std::to_string(node) + " does not exist");
      }
      if (state_[node] == 1) fail("node graph has a cycle through node " + std::to_string(node));
      // A tree visits each node once; a DAG (nodes reused by several parents) can visit one
      // node 2^depth times.
      if (++instances_ > m_.nodes.size() + kMaxReusedNodes) {
        fail("the node graph reuses nodes more than " + std::to_string(kMaxReusedNodes) +
             " times (nodes with several parents)");
      }
      const tinygltf::Node& n = m_.nodes[node];
      check_transform(n, node);
      const glm::dmat4 world = parent_world * node_local_matrix(n);
      state_[node] = 1;
      emit_node(n, node, world);
      stack.push_back(Frame{node, world, 0});
    };
    enter(root, parent, -1);
    while (!stack.empty()) {
      Frame& f = stack.back();
      const tinygltf::Node& n = m_.nodes[f.node];
      if (f.next_child < n.children.size()) {
        const int child = n.children[f.next_child++];
        const glm::dmat4 world = f.world;  // f may dangle after push_back
        enter(child, world, f.node);
      } else {
        state_[f.node] = 0;
        stack.pop_back();
      }
    }
  }

  void check_transform(const tinygltf::Node& n, int index) const {
    // No strings unless it fails: this runs on every visit of a node.
    auto where = [&] { return "node " + std::to_string(index); };
    auto check = [&](const std::vector<double>& v, std::size_t want, const char* name) {
      if (!v.empty() && v.size() != want) {
        fail(where() + ": " + name + " has " + std::to_string(v.size()) + " numbers, expected " +
             std::to_string(want));
      }
      for (double d : v) {
        if (!std::isfinite(d)) fail(where() + ": " + name + " is not finite");
      }
    };
    check(n.matrix, 16, "matrix");
    check(n.translation, 3, "translation");
    check(n.rotation, 4, "rotation");
    check(n.scale, 3, "scale");
  }

  void emit_node(const tinygltf::Node& n, int index, const glm::dmat4& world) {
    if (n.mesh >= 0) {
      if (static_cast<std::size_t>(n.mesh) >= m_.meshes.size()) {
        fail("node " + std::to_string(index) + ": mesh " + std::to_string(n.mesh) +
             " does not exist");
      }
      emit_mesh(n.mesh, world);
    } else if (n.mesh < -1) {
      fail("node " + std::to_string(index) + ": mesh " + std::to_string(n.mesh) +
           " does not exist");
    }
    if (n.camera >= 0) emit_camera(n, index, world);
    auto lit = n.extensions.find("KHR_lights_punctual");
    if (lit != n.extensions.end() && lit->second.IsObject() && lit->second.Has("light")) {
      const tinygltf::Value& l = lit->second.Get("light");
      if (!l.IsNumber()) fail("node " + std::to_string(index) + ": light index is not a number");
      emit_light(l.GetNumberAsInt(), index, world);
    }
  }

  void emit_camera(const tinygltf::Node& n, int index, const glm::dmat4& world) {
    if (static_cast<std::size_t>(n.camera) >= m_.cameras.size()) {
      fail("node " + std::to_string(index) + ": camera " + std::to_string(n.camera) +
           " does not exist");
    }
    const tinygltf::Camera& gc = m_.cameras[n.camera];
    if (gc.type != "perspective") return;  // orthographic cameras are not supported: skipped
    Camera cam;
    cam.name = !gc.name.empty() ? gc.name : (!n.name.empty() ? n.name : "camera " +
                                                                           std::to_string(n.camera));
    const glm::dmat3 r(world);
    cam.position = glm::vec3(world[3]);
    glm::dvec3 fwd = r * glm::dvec3(0, 0, -1);
    glm::dvec3 up = r * glm::dvec3(0, 1, 0);
    if (!(glm::length(fwd) > 0.0)) fail("camera node " + std::to_string(index) + " is degenerate");
    fwd = glm::normalize(fwd);
    up = up - glm::dot(up, fwd) * fwd;
    if (!(glm::length(up) > 0.0)) fail("camera node " + std::to_string(index) + " is degenerate");
    cam.forward = glm::vec3(fwd);
    cam.up = glm::vec3(glm::normalize(up));
    cam.yfov = static_cast<float>(gc.perspective.yfov);
    cam.aspect = static_cast<float>(gc.perspective.aspectRatio);
    if (!(cam.yfov > 0.0f && cam.yfov < 3.14159f)) {
      fail("camera " + std::to_string(n.camera) + ": yfov " + std::to_string(cam.yfov) +
           " is out of range");
    }
    if (!(cam.aspect >= 0.0f) || !std::isfinite(cam.aspect)) {
      fail("camera " + std::to_string(n.camera) + ": invalid aspectRatio");
    }
    scene_.cameras.push_back(cam);
  }

  void emit_light(int light, int index, const glm::dmat4& world) {
    if (light < 0 || static_cast<std::size_t>(light) >= m_.lights.size()) {
      fail("node " + std::to_string(index) + ": KHR_lights_punctual light " +
           std::to_string(light) + " does not exist");
    }
    const tinygltf::Light& gl = m_.lights[light];
    Light out;
    if (gl.type == "point") {
      out.type = LightType::kPoint;
    } else if (gl.type == "spot") {
      out.type = LightType::kSpot;
    } else if (gl.type == "directional") {
      out.type = LightType::kDirectional;
    } else {
      fail("light " + std::to_string(light) + ": unknown type \"" + gl.type + "\"");
    }
    out.color = to_vec3(gl.color, glm::vec3(1.0f)) * static_cast<float>(gl.intensity);
    out.position = glm::vec3(world[3]);
    glm::dvec3 dir = glm::dmat3(world) * glm::dvec3(0, 0, -1);
    if (glm::length(dir) > 0.0) dir = glm::normalize(dir);
    out.direction = glm::vec3(dir);
    out.inner_cone = static_cast<float>(gl.spot.innerConeAngle);
    out.outer_cone = static_cast<float>(gl.spot.outerConeAngle);
    out.range = static_cast<float>(gl.range);
    if (!std::isfinite(out.color.x + out.color.y + out.color.z) || !(out.range >= 0.0f)) {
      fail("light " + std::to_string(light) + " has invalid values");
    }
    scene_.lights.push_back(out);
  }

  // ---- geometry ------------------------------------------------------------------------------
  // A primitive's vertices in world space; wn and uv empty when it has no normals / texcoords.
  struct WorldVertices {
    std::vector<glm::vec3> wp, wn;
    std::vector<glm::vec2> uv;
    std::vector<std::uint32_t> rgb;  // vertex colours, TriangleShading's packing
  };

  void emit_mesh(int mesh_index, const glm::dmat4& world) {
    const tinygltf::Mesh& mesh = m_.meshes[mesh_index];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p)
      emit_primitive(mesh_index, static_cast<int>(p), world);
  }

  void emit_primitive(int mesh_index, int p, const glm::dmat4& world) {
    const tinygltf::Primitive& prim = m_.meshes[mesh_index].primitives[p];
    const std::string where = "mesh " + std::to_string(mesh_index) + " primitive " +
                              std::to_string(p);
    const int mode = prim.mode < 0 ? kGltfTriangles : prim.mode;
    if (is_point_or_line_mode(mode)) {
      skipped_.insert({mesh_index, p});
      return;
    }
    if (mode > kGltfTriangleFan) {
      fail(where + ": mode " + std::to_string(mode) + " (" + gltf_mode_name(mode) +
           ") is not supported, only TRIANGLES (4), TRIANGLE_STRIP (5) and TRIANGLE_FAN (6)");
    }
    auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end()) fail(where + " has no POSITION attribute");
    const AccessorView pos = attribute(pos_it->second, kPosition);
    const std::optional<AccessorView> nrm = optional_attribute(prim, kNormal, pos.count);
    const std::optional<AccessorView> tc = optional_attribute(prim, kTexcoord, pos.count);
    const std::optional<AccessorView> col = optional_attribute(prim, kColor, pos.count);
    WorldVertices v = world_vertices(pos, pos_it->second, nrm, tc, world);
    if (col) v.rgb = vertex_colors(*col, prim.attributes.at(kColor.semantic));
    std::vector<std::uint32_t> sequence = vertex_sequence(prim, where, pos.count);
    if (mode == kGltfTriangles && sequence.size() % 3 != 0) {  // a warning in the spec's validator
      ragged_.insert({mesh_index, p});
      sequence.resize(sequence.size() / 3 * 3);
    }
    const std::uint32_t material = material_for(prim.material, mesh_index, p);
    if (prim.material >= 0) transform_texcoords(prim.material, v.uv);
    emit_triangles(triangle_list(mode, std::move(sequence)), v, material);
  }

  AccessorView attribute(int accessor, const AttributeFormat& f) {
    const AccessorView v = reader_.view(accessor, f.semantic);
    const int bit = v.component_type - TINYGLTF_COMPONENT_TYPE_BYTE;
    const bool is_float = v.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT && !v.normalized;
    const bool is_int = bit >= 0 && bit < 4 && ((f.integers >> bit) & 1u) != 0 &&
                        (v.normalized || !f.normalized_only);
    if ((v.type != f.type && v.type != f.other_type) || (!is_float && !is_int)) {
      fail("accessor " + std::to_string(accessor) + " (" + f.semantic + ") is " + v.format() +
           ", expected " + f.expected);
    }
    return v;
  }

  std::optional<AccessorView> optional_attribute(const tinygltf::Primitive& prim,
                                                 const AttributeFormat& f, std::size_t vertices) {
    auto it = prim.attributes.find(f.semantic);
    if (it == prim.attributes.end()) return std::nullopt;
    const AccessorView v = attribute(it->second, f);
    if (v.count != vertices) {
      fail("accessor " + std::to_string(it->second) + " (" + f.semantic + ") has " +
           std::to_string(v.count) + " elements, POSITION has " + std::to_string(vertices));
    }
    return v;
  }

  // Transforms every vertex once.
  WorldVertices world_vertices(const AccessorView& pos, int pos_accessor,
                               const std::optional<AccessorView>& nrm,
                               const std::optional<AccessorView>& tc, const glm::dmat4& world) {
    const std::size_t nv = pos.count;
    WorldVertices v;
    v.wp.resize(nv);
    for (std::size_t i = 0; i < nv; ++i) {
      const glm::dvec3 p(pos.read_float(i, 0), pos.read_float(i, 1), pos.read_float(i, 2));
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        fail("accessor " + std::to_string(pos_accessor) +
             " (POSITION) has a non-finite value (NaN or Inf) at element " + std::to_string(i));
      }
      v.wp[i] = glm::vec3(world * glm::dvec4(p, 1.0));
      if (!std::isfinite(v.wp[i].x) || !std::isfinite(v.wp[i].y) || !std::isfinite(v.wp[i].z)) {
        fail("accessor " + std::to_string(pos_accessor) + " (POSITION) element " +
             std::to_string(i) + " is out of float range after the node transform");
      }
    }
    if (nrm) {
      const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(world)));
      v.wn.resize(nv);
      for (std::size_t i = 0; i < nv; ++i) {
        glm::dvec3 n(nrm->read_float(i, 0), nrm->read_float(i, 1), nrm->read_float(i, 2));
        n = normal_matrix * n;
        const double len = glm::length(n);
        v.wn[i] = (len > 0.0 && std::isfinite(len)) ? glm::vec3(n / len) : glm::vec3(0.0f);
      }
    }
    if (tc) {
      v.uv.resize(nv);
      for (std::size_t i = 0; i < nv; ++i) v.uv[i] = glm::vec2(tc->read_float(i, 0), tc->read_float(i, 1));
    }
    return v;
  }

  // COLOR_0 as TriangleShading packs it (alpha is not used): 8 bits a channel, clamped to [0, 1].
  std::vector<std::uint32_t> vertex_colors(const AccessorView& col, int accessor) {
    std::vector<std::uint32_t> rgb(col.count);
    for (std::size_t i = 0; i < col.count; ++i) {
      for (int c = 0; c < 3; ++c) {
        const float x = col.read_float(i, c);
        if (!std::isfinite(x)) {
          fail("accessor " + std::to_string(accessor) +
               " (COLOR_0) has a non-finite value (NaN or Inf) at element " + std::to_string(i));
        }
        const float unit = std::clamp(x, 0.0f, 1.0f);
        rgb[i] |= static_cast<std::uint32_t>(std::lround(unit * 255.0f)) << (8 * c);
      }
    }
    return rgb;
  }

  // The primitive's vertex sequence: its indices (each checked against the vertex count), or
  // 0..vertices-1 when it has none.
  std::vector<std::uint32_t> vertex_sequence(const tinygltf::Primitive& prim,
                                             const std::string& where, std::size_t vertices) {
    std::vector<std::uint32_t> sequence;
    if (prim.indices < -1) {
      fail(where + ": indices accessor " + std::to_string(prim.indices) + " does not exist");
    }
    if (prim.indices < 0) {
      sequence.resize(vertices);
      for (std::size_t i = 0; i < vertices; ++i) sequence[i] = static_cast<std::uint32_t>(i);
      return sequence;
    }
    const AccessorView idx = reader_.view(prim.indices, "indices");
    if (idx.type != TINYGLTF_TYPE_SCALAR ||
        (idx.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
         idx.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
         idx.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
      fail("accessor " + std::to_string(prim.indices) + " (indices) is " + idx.format() +
           ", expected SCALAR UNSIGNED_BYTE/UNSIGNED_SHORT/UNSIGNED_INT");
    }
    sequence.resize(idx.count);
    for (std::size_t e = 0; e < idx.count; ++e) {
      sequence[e] = idx.read_index(e);
      if (sequence[e] >= vertices) {
        fail("accessor " + std::to_string(prim.indices) + " (indices): index " +
             std::to_string(sequence[e]) + " at element " + std::to_string(e) +
             " is out of range (vertex count " + std::to_string(vertices) + ")");
      }
    }
    return sequence;
  }

  // Appends the triangles of a triangle list (indices checked by vertex_sequence).
  void emit_triangles(const std::vector<std::uint32_t>& list, const WorldVertices& v,
                      std::uint32_t material) {
    const std::size_t nt = list.size() / 3;
    if (nt > kMaxTriangles - scene_.triangles.size()) {
      fail("more than " + std::to_string(kMaxTriangles) + " triangles");
    }
    // No reserve(size + nt) here: once per instance, it would defeat the vectors' geometric
    // growth and copy every triangle loaded so far (quadratic in the instance count).
    for (std::size_t t = 0; t < nt; ++t) {
      const std::uint32_t* k = &list[3 * t];
      scene_.triangles.push_back(Triangle{v.wp[k[0]], v.wp[k[1]], v.wp[k[2]]});
      TriangleShading s;
      if (!v.wn.empty()) {
        s.n0 = v.wn[k[0]];
        s.n1 = v.wn[k[1]];
        s.n2 = v.wn[k[2]];
      }
      if (!v.rgb.empty()) {
        s.c0 = v.rgb[k[0]];
        s.c1 = v.rgb[k[1]];
        s.c2 = v.rgb[k[2]];
      }
      if (!v.uv.empty()) {
        s.uv0 = v.uv[k[0]];
        s.uv1 = v.uv[k[1]];
        s.uv2 = v.uv[k[2]];
      }
      s.material = material;
      scene_.shading.push_back(s);
    }
  }

  const tinygltf::Model& m_;
  AccessorReader reader_{m_};
  std::string file_;
  Scene& scene_;
  struct TextureSlots {  // a glTF material's texture indices, -1: none
    int base_color, metallic_roughness, emissive;
  };
  std::vector<TextureSlots> slots_;     // per glTF material
  std::vector<int> texture_of_image_;   // glTF image -> Scene::textures index, -1: not decoded
  std::set<int> texture_resolved_;
  std::vector<std::uint8_t> state_;     // per node: 1 while on the current path
  std::size_t instances_ = 0;           // nodes entered so far, over every path
  int default_material_ = -1;
  std::vector<std::optional<glm::mat3>> uv_transform_;  // per glTF material: KHR_texture_transform
  bool texcoord_override_ = false;
  std::set<std::pair<int, int>> skipped_;  // (mesh, primitive) of points and lines skipped
  std::set<std::pair<int, int>> ragged_;   // TRIANGLES (mesh, primitive) with 3n + 1 or 2 indices
};

std::uint32_t u32_at(const std::vector<unsigned char>& bytes, std::size_t offset) {
  std::uint32_t v = 0;  // little-endian host (x86-64, aarch64)
  if (bytes.size() >= offset + 4) std::memcpy(&v, bytes.data() + offset, 4);
  return v;
}

// A glTF file's bytes and where its JSON lies in them (a .gltf: all of them).
struct GltfFile {
  std::vector<unsigned char> bytes;
  bool binary = false;  // parsed as GLB: a .glb, or the GLB magic under another extension
  bool glb = false;     // binary, and starts with the GLB magic
  std::size_t json_begin = 0, json_end = 0;
  std::size_t json_size() const { return json_end - json_begin; }
};

// A GLB's JSON chunk; refuses other versions than 2 and a BIN chunk past the end of the file.
void locate_glb_json(GltfFile& f, const std::string& name) {
  const std::vector<unsigned char>& b = f.bytes;
  // tinygltf reads any GLB version; glTF 2.0 is version 2 (version 1 is the glTF 1.0 format).
  if (u32_at(b, 4) != 2) {
    throw Error(name + ": GLB version " + std::to_string(u32_at(b, 4)) +
                " is not supported (glTF 2.0 files are version 2)");
  }
  f.json_begin = std::min<std::size_t>(20, b.size());
  f.json_end = f.json_begin + std::min<std::size_t>(u32_at(b, 12), b.size() - f.json_begin);
  // tinygltf 2.7 checks the BIN chunk's length against the header's total without the
  // chunk's own 8-byte header: a chunk up to 8 bytes longer than the file would be read past
  // its end.
  const std::uint64_t bin = std::uint64_t{20} + u32_at(b, 12);
  if (u32_at(b, 8) <= b.size() && bin + 8 <= b.size() && bin + 8 + u32_at(b, bin) > b.size()) {
    throw Error(name + ": the BIN chunk (" + std::to_string(u32_at(b, bin)) +
                " bytes) lies past the end of the file");
  }
}

GltfFile read_gltf_file(const std::filesystem::path& file, const std::string& name) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw Error(name + ": no such file");
  if (std::filesystem::is_directory(file, ec)) throw Error(name + ": is a directory");
  GltfFile f;
  std::string err;
  if (!read_whole_file(&f.bytes, &err, name, nullptr)) throw Error(name + ": " + err);
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const bool magic = f.bytes.size() >= 4 && std::memcmp(f.bytes.data(), "glTF", 4) == 0;
  // Unknown extension: sniff the GLB magic.
  f.binary = ext == ".glb" || (ext != ".gltf" && magic);
  f.glb = f.binary && magic;
  f.json_end = f.bytes.size();
  if (f.glb && f.bytes.size() >= 12) locate_glb_json(f, name);
  return f;
}

// tinygltf's file callbacks with read_whole_file as the reader, which makes every check, so that
// tinygltf 2.7 (Debian 12) and 2.9 (Debian 13) refuse a file alike: a path exists if anything
// is there (2.9's own check passes no directory, whose refusal would then read "not found");
// 2.9's size query, called before the reader, leaves the size to it. 2.9 refuses a set with
// any callback missing.
bool exists_at_all(const std::string& path, void* /*user_data*/) {
  std::error_code ec;
  return std::filesystem::exists(path, ec);
}

[[maybe_unused]] bool size_left_to_reader(std::size_t* size, std::string*, const std::string&,
                                          void*) {  // (unused with tinygltf 2.7)
  *size = 0;
  return true;
}

template <class Callbacks>  // tinygltf::FsCallbacks; a template, so one branch can be discarded
void set_file_callbacks(tinygltf::TinyGLTF& gltf, Callbacks fs) {
  fs.FileExists = &exists_at_all;
  fs.ExpandFilePath = &tinygltf::ExpandFilePath;
  fs.ReadWholeFile = &read_whole_file;
  fs.WriteWholeFile = &tinygltf::WriteWholeFile;
  if constexpr (requires { fs.GetFileSizeInBytes; }) {
    fs.GetFileSizeInBytes = &size_left_to_reader;
    std::string err;
    if (!gltf.SetFsCallbacks(fs, &err)) throw Error("tinygltf: " + err);
  } else {
    gltf.SetFsCallbacks(fs);
  }
}

// tinygltf's model of the file; one line naming the file when it cannot parse it.
tinygltf::Model parse_model(const GltfFile& f, const std::string& base_dir,
                            const std::string& name) {
  tinygltf::TinyGLTF gltf;
  gltf.SetImageLoader(defer_image, nullptr);
  set_file_callbacks(gltf, tinygltf::FsCallbacks{});
  tinygltf::Model model;
  std::string err, warn;
  const auto size = static_cast<unsigned int>(f.bytes.size());  // < 4 GiB: read_whole_file
  const bool ok =
      f.binary
          ? gltf.LoadBinaryFromMemory(&model, &err, &warn, f.bytes.data(), size, base_dir)
          : gltf.LoadASCIIFromString(&model, &err, &warn,
                                     reinterpret_cast<const char*>(f.bytes.data()), size, base_dir);
  if (ok) return model;
  if (err.empty()) err = "cannot be parsed as glTF";
  // Say so when the GLB header promises more bytes than the file has.
  if (f.glb && f.bytes.size() >= 12 && u32_at(f.bytes, 8) > f.bytes.size()) {
    err += " (truncated: the header says " + std::to_string(u32_at(f.bytes, 8)) +
           " bytes, the file has " + std::to_string(f.bytes.size()) + ")";
  }
  throw Error(one_line(name + ": " + err));
}

// Decodes the compressed data (meshopt views, Draco primitives), then flattens the model.
Scene load_model(tinygltf::Model& model, const std::string& name, const GltfPrepass& pre) {
  try {
    decode_meshopt_views(model);
    decode_draco_primitives(model, pre.draco_indices);
  } catch (const GltfError& e) {
    throw Error(one_line(name + ": " + e.what()));
  }
  Scene scene;
  scene.name = std::filesystem::path(name).filename().string();
  for (const std::string& w : pre.warnings) scene.warnings.push_back(name + ": " + w);
  GltfLoader(model, name, scene).load();
  for (const std::string& w : scene.warnings) {
    std::fprintf(stderr, "hrpp: warning: %s\n", w.c_str());
  }
  return scene;
}

}  // namespace

Scene load_gltf(const std::filesystem::path& file) {
  const std::string name = file.string();
  GltfFile f = read_gltf_file(file, name);
  // tinygltf converts JSON values recursively: deep nesting would overflow the stack.
  const std::size_t depth = json_nesting_depth(f.bytes.data() + f.json_begin, f.json_size());
  if (depth > kMaxJsonDepth) {
    throw Error(name + ": JSON nested " + std::to_string(depth) + " levels deep (at most " +
                std::to_string(kMaxJsonDepth) + ")");
  }
  GltfPrepass pre;
  try {
    pre = gltf_prepass(f.bytes.data() + f.json_begin, f.json_size());
  } catch (const GltfError& e) {
    throw Error(one_line(name + ": " + e.what()));
  }
  // A GLB is rebuilt only when its header's length is the file's: tinygltf refuses the others.
  if (pre.changed && (!f.glb || u32_at(f.bytes, 8) == f.bytes.size())) {
    f.bytes = replace_json(f.bytes, f.glb, f.json_end, pre.json);
  }
  tinygltf::Model model = parse_model(f, file.parent_path().string(), name);
  return load_model(model, name, pre);
}

}  // namespace hrpp
