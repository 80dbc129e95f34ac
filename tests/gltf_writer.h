// Test helper: composes glTF 2.0 files in code and writes them as .gltf (+ .bin or a data URI) or
// .glb. Everything stays editable (the JSON document and the binary buffer are public members), so
// tests can also write MALFORMED files: out-of-range accessors, bad modes, NaN positions, cycles,
// truncated or wrongly tagged GLB files.
//
// Typical use:
//   hrpp::test::GltfWriter w;
//   int mesh = w.add_triangles({{0,0,0}, {1,0,0}, {0,1,0}});          // one TRIANGLES primitive
//   w.add_scene({w.add_node(mesh)});                                    // default scene
//   w.write(dir / "tri.glb");                                           // container from extension
//
// Low level: add_buffer_view() appends raw bytes to buffer 0, add_accessor() describes them,
// primitive() builds a primitive object, add_mesh()/add_node()/add_material()... append to the
// document and return the new index. `doc` and `bin` may be edited directly at any point.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace hrpp::test {

// glTF constants.
inline constexpr int kUnsignedByte = 5121, kUnsignedShort = 5123, kUnsignedInt = 5125,
                     kFloat = 5126;
inline constexpr int kModePoints = 0, kModeLines = 1, kModeTriangles = 4, kModeTriangleStrip = 5,
                     kModeTriangleFan = 6;

class GltfWriter {
 public:
  enum class Container {
    kAuto,          // from the file extension: .glb → kGlb, otherwise kGltfBin
    kGltfBin,       // FILE.gltf + FILE.bin (the .bin next to it, same stem)
    kGltfDataUri,   // FILE.gltf with the buffer embedded as a base64 data URI
    kGlb,           // binary container
  };

  nlohmann::json doc;              // the glTF JSON; "buffers" is filled in by write()
  std::vector<std::uint8_t> bin;   // contents of buffer 0

  GltfWriter();

  // Appends bytes to buffer 0 (at a 4-byte aligned offset) and adds a bufferView over them.
  // stride 0 omits byteStride. Returns the bufferView index.
  int add_buffer_view(const void* data, std::size_t bytes, std::size_t stride = 0);
  // Adds an accessor; type is "SCALAR", "VEC2", "VEC3"...; byte_offset 0 omits it.
  int add_accessor(int buffer_view, int component_type, std::size_t count, const std::string& type,
                   std::size_t byte_offset = 0, bool normalized = false);
  // Convenience: data + bufferView + accessor in one call.
  int add_vec3(const std::vector<glm::vec3>& v);   // FLOAT VEC3 (with min/max when finite)
  int add_vec2(const std::vector<glm::vec2>& v);   // FLOAT VEC2
  // Indices stored as kUnsignedByte, kUnsignedShort or kUnsignedInt (values are truncated).
  int add_indices(const std::vector<std::uint32_t>& idx, int component_type = kUnsignedInt);

  // A primitive object; -1 leaves an attribute out. Pass it to add_mesh.
  static nlohmann::json primitive(int position, int indices = -1, int material = -1,
                                  int normal = -1, int texcoord0 = -1, int mode = kModeTriangles);
  int add_mesh(const std::vector<nlohmann::json>& primitives);
  // One-primitive mesh from positions (+ optional indices, stored as index_type) and material.
  int add_triangles(const std::vector<glm::vec3>& positions,
                    const std::vector<std::uint32_t>& indices = {}, int material = -1,
                    int index_type = kUnsignedInt);

  // Nodes: mesh/camera -1 leave them out. Extra members (matrix, translation, rotation, scale,
  // children, extensions) can be added to the returned index via doc["nodes"][i].
  int add_node(int mesh = -1, const std::vector<int>& children = {});
  // Adds a scene with these root nodes; the first scene added becomes doc["scene"].
  int add_scene(const std::vector<int>& roots);
  int add_material(const nlohmann::json& material);     // appended as is
  int add_camera_perspective(float yfov, float aspect = 0.0f);  // aspect 0: omitted
  // KHR_lights_punctual light (declares the extension); attach with attach_light(node, light).
  int add_light(const nlohmann::json& light);
  void attach_light(int node, int light);
  // A PNG stored in a bufferView (image) plus a texture using it; returns the texture index.
  int add_png_texture(const std::vector<std::uint8_t>& png);

  // Serialisation. The GLB bytes are available for tests that corrupt them.
  std::vector<std::uint8_t> glb_bytes() const;
  std::string json_text(const std::string& buffer_uri) const;  // buffer_uri "" → no buffers
  void write(const std::filesystem::path& file, Container container = Container::kAuto) const;

 private:
  int append(const char* array, const nlohmann::json& value);
};

// An uncompressed (stored-deflate) 8-bit RGBA PNG; rgba has width*height*4 bytes, rows top first.
std::vector<std::uint8_t> make_png(int width, int height, const std::vector<std::uint8_t>& rgba);

// Writes bytes to a file (throws std::runtime_error on failure).
void write_file(const std::filesystem::path& file, const std::vector<std::uint8_t>& bytes);
void write_file(const std::filesystem::path& file, const std::string& text);

// A fresh empty directory under the system temp dir, e.g. /tmp/hrpp-scene_test-1234-0.
std::filesystem::path make_temp_dir(const std::string& tag);

}  // namespace hrpp::test
