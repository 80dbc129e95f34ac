// glTF encodings the loader reads besides plain FLOAT triangles: quantized attributes
// (KHR_mesh_quantization, dequantized as the spec says), sparse accessors, KHR_texture_transform
// on a material's textures, the extensions it honours or refuses, and the corpus of one mesh
// in each encoding (meshopt, Draco, quantized; tests/data/gltf_encodings).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "cpu_render/cpu_renderer.h"
#include "gltf_file_test.h"
#include "gltf_writer.h"
#include "scene/gltf_prepass.h"
#include "scene/load_scene.h"

namespace hrpp::test {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const std::array<std::uint8_t, 4> kZeros = {0, 0, 0, 0};
constexpr int kByte = 5120, kShort = 5122;  // kUnsignedByte, kUnsignedShort: gltf_writer.h

// Integer vectors of N components of type T, each element padded to 4 bytes (the vertex
// attribute alignment), in a bufferView with that byteStride; returns the accessor.
template <typename T, std::size_t N>
int add_ints(GltfWriter& w, const std::vector<std::array<T, N>>& v, int component_type,
             bool normalized) {
  const std::size_t stride = (N * sizeof(T) + 3) / 4 * 4;
  std::vector<std::uint8_t> bytes(v.size() * stride, 0xEE);  // padding: not zeros
  for (std::size_t i = 0; i < v.size(); ++i)
    std::memcpy(&bytes[i * stride], v[i].data(), N * sizeof(T));
  const int bv = w.add_buffer_view(bytes.data(), bytes.size(), stride);
  return w.add_accessor(bv, component_type, v.size(), "VEC" + std::to_string(N), 0, normalized);
}

// The CPU reference renderer's image of `s`: size x size pixels, spp samples, seed 7.
std::vector<float> cpu_image(const Scene& s, std::uint32_t size, std::uint32_t spp) {
  RenderConfig config;
  config.width = config.height = size;
  config.spp = spp;
  config.seed = 7;
  const GpuBvh bvh = make_gpu_layout(build_bvh(s), s);
  return CpuRenderer(s, bvh, config).render().rgb;
}

class GltfEncodings : public hrpp::test::GltfFileTest {
 protected:
  // One non-indexed triangle primitive over these accessors (-1: none).
  Scene load_triangle(GltfWriter& w, int pos, int nrm = -1, int uv = -1, int material = -1) {
    w.add_scene({w.add_node(w.add_mesh({GltfWriter::primitive(pos, -1, material, nrm, uv)}))});
    return load(w);
  }
};

// The three vertices of the scene's only triangle.
std::array<glm::vec3, 3> vertices(const Scene& s) {
  EXPECT_EQ(s.triangles.size(), 1u);
  if (s.triangles.empty()) return {};
  return {s.triangles[0].v0, s.triangles[0].v1, s.triangles[0].v2};
}

TEST_F(GltfEncodings, NormalizedSignedPositionsDequantizeAsTheSpecSays) {
  {
    GltfWriter w;
    const int pos =
        add_ints<std::int8_t, 3>(w, {{-128, -127, 0}, {127, 64, 1}, {-1, 0, 5}}, kByte, true);
    const auto v = vertices(load_triangle(w, pos));
    // max(c / 127, -1): -128 and -127 both give -1.
    EXPECT_EQ(v[0], glm::vec3(-1.0f, -1.0f, 0.0f));
    EXPECT_EQ(v[1], glm::vec3(1.0f, 64.0f / 127.0f, 1.0f / 127.0f));
    EXPECT_EQ(v[2], glm::vec3(-1.0f / 127.0f, 0.0f, 5.0f / 127.0f));
  }
  {
    GltfWriter w;
    const int pos = add_ints<std::int16_t, 3>(
        w, {{-32768, -32767, 0}, {32767, 1000, 1}, {-1, 0, 5}}, kShort, true);
    const auto v = vertices(load_triangle(w, pos));
    EXPECT_EQ(v[0], glm::vec3(-1.0f, -1.0f, 0.0f));
    EXPECT_EQ(v[1], glm::vec3(1.0f, 1000.0f / 32767.0f, 1.0f / 32767.0f));
    EXPECT_EQ(v[2], glm::vec3(-1.0f / 32767.0f, 0.0f, 5.0f / 32767.0f));
  }
}

TEST_F(GltfEncodings, NormalizedUnsignedPositionsDequantizeAsTheSpecSays) {
  {
    GltfWriter w;
    const int pos =
        add_ints<std::uint8_t, 3>(w, {{0, 255, 1}, {128, 0, 0}, {0, 7, 0}}, kUnsignedByte, true);
    const auto v = vertices(load_triangle(w, pos));
    EXPECT_EQ(v[0], glm::vec3(0.0f, 1.0f, 1.0f / 255.0f));
    EXPECT_EQ(v[1], glm::vec3(128.0f / 255.0f, 0.0f, 0.0f));
    EXPECT_EQ(v[2], glm::vec3(0.0f, 7.0f / 255.0f, 0.0f));
  }
  {
    GltfWriter w;
    const int pos = add_ints<std::uint16_t, 3>(w, {{0, 65535, 1}, {40000, 0, 0}, {0, 7, 0}},
                                               kUnsignedShort, true);
    const auto v = vertices(load_triangle(w, pos));
    EXPECT_EQ(v[0], glm::vec3(0.0f, 1.0f, 1.0f / 65535.0f));
    EXPECT_EQ(v[1], glm::vec3(40000.0f / 65535.0f, 0.0f, 0.0f));
  }
}

// Unnormalized integers are the numbers themselves; the node transform (gltfpack's and
// glTF-Transform's dequantization scale and offset) applies after.
TEST_F(GltfEncodings, UnnormalizedIntegerPositionsAreTheirValues) {
  for (int type : {kByte, kUnsignedByte, kShort, kUnsignedShort}) {
    GltfWriter w;
    int pos = -1;
    if (type == kByte)
      pos = add_ints<std::int8_t, 3>(w, {{0, 0, 0}, {-3, 0, 0}, {0, 100, 0}}, type, false);
    if (type == kUnsignedByte)
      pos = add_ints<std::uint8_t, 3>(w, {{0, 0, 0}, {3, 0, 0}, {0, 200, 0}}, type, false);
    if (type == kShort)
      pos = add_ints<std::int16_t, 3>(w, {{0, 0, 0}, {-3, 0, 0}, {0, 30000, 0}}, type, false);
    if (type == kUnsignedShort)
      pos = add_ints<std::uint16_t, 3>(w, {{0, 0, 0}, {3, 0, 0}, {0, 60000, 0}}, type, false);
    const int node = w.add_node(w.add_mesh({GltfWriter::primitive(pos)}));
    w.doc["nodes"][node]["translation"] = {1, 2, 3};
    w.doc["nodes"][node]["scale"] = {0.5, 0.25, 1};
    w.add_scene({node});
    const auto v = vertices(load(w));
    const bool is_signed = type == kByte || type == kShort;
    const float y = type == kByte           ? 100.0f
                    : type == kUnsignedByte ? 200.0f
                    : type == kShort        ? 30000.0f
                                            : 60000.0f;
    EXPECT_EQ(v[0], glm::vec3(1, 2, 3)) << type;
    EXPECT_EQ(v[1], glm::vec3(1.0f + 0.5f * (is_signed ? -3.0f : 3.0f), 2, 3)) << type;
    EXPECT_EQ(v[2], glm::vec3(1.0f, 2.0f + 0.25f * y, 3.0f)) << type;
  }
}

TEST_F(GltfEncodings, QuantizedNormalsAndTexcoords) {
  GltfWriter w;
  const int pos = w.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int nrm =
      add_ints<std::int8_t, 3>(w, {{0, 0, 127}, {0, -128, 0}, {127, 127, 0}}, kByte, true);
  const int uv =
      add_ints<std::uint16_t, 2>(w, {{0, 65535}, {32768, 0}, {65535, 65535}}, kUnsignedShort, true);
  const Scene s = load_triangle(w, pos, nrm, uv);
  ASSERT_EQ(s.shading.size(), 1u);
  EXPECT_EQ(s.shading[0].n0, glm::vec3(0, 0, 1));
  EXPECT_EQ(s.shading[0].n1, glm::vec3(0, -1, 0));
  EXPECT_NEAR(s.shading[0].n2.x, std::sqrt(0.5f), 1e-6f);  // renormalised after dequantizing
  EXPECT_EQ(s.shading[0].uv0, glm::vec2(0, 1));
  EXPECT_EQ(s.shading[0].uv1, glm::vec2(32768.0f / 65535.0f, 0));

  GltfWriter u;  // unnormalized SHORT texcoords: the numbers (a texture transform scales them)
  const int upos = u.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int uuv = add_ints<std::int16_t, 2>(u, {{-2, 3}, {0, 0}, {1, 1}}, kShort, false);
  EXPECT_EQ(load_triangle(u, upos, -1, uuv).shading[0].uv0, glm::vec2(-2, 3));
}

TEST_F(GltfEncodings, FormatsOutsideTheSpecAreRefusedNamingTheAccessor) {
  {
    GltfWriter w;  // NORMAL must be normalized and signed
    const int pos = w.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    const int nrm =
        add_ints<std::uint8_t, 3>(w, {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}}, kUnsignedByte, true);
    expect_error([&] { load_triangle(w, pos, nrm); }, path(),
                 "accessor 1 (NORMAL) is normalized UNSIGNED_BYTE VEC3, expected FLOAT VEC3 or "
                 "normalized BYTE/SHORT VEC3");
  }
  {
    GltfWriter w;  // POSITION as UNSIGNED_INT is not in KHR_mesh_quantization
    std::vector<std::uint32_t> p = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const int bv = w.add_buffer_view(p.data(), p.size() * 4);
    const int pos = w.add_accessor(bv, 5125, 3, "VEC3");
    expect_error([&] { load_triangle(w, pos); }, path(),
                 "accessor 0 (POSITION) is UNSIGNED_INT VEC3, expected FLOAT VEC3 or");
  }
}

// Accessor `acc` of `w` made sparse: `indices` (UNSIGNED_SHORT) replaced by `values` (FLOAT VEC3).
void make_sparse(GltfWriter& w, int acc, const std::vector<std::uint16_t>& indices,
                 const std::vector<glm::vec3>& values) {
  const int ibv = w.add_buffer_view(indices.data(), indices.size() * 2);
  const int vbv = w.add_buffer_view(values.data(), values.size() * sizeof(glm::vec3));
  w.doc["accessors"][acc]["sparse"] = {
      {"count", indices.size()},
      {"indices", {{"bufferView", ibv}, {"componentType", kUnsignedShort}}},
      {"values", {{"bufferView", vbv}}}};
}

TEST_F(GltfEncodings, SparseAccessorsSubstituteTheirElements) {
  GltfWriter w;
  const int pos = w.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  make_sparse(w, pos, {2}, {{0, 5, 0}});
  const auto v = vertices(load_triangle(w, pos));
  EXPECT_EQ(v[1], glm::vec3(1, 0, 0));
  EXPECT_EQ(v[2], glm::vec3(0, 5, 0));

  GltfWriter z;  // no bufferView: zeros, then the sparse elements
  const int zbv = z.add_buffer_view(kZeros.data(), 4);
  const int zpos = z.add_accessor(zbv, 5126, 3, "VEC3");
  z.doc["accessors"][zpos].erase("bufferView");
  make_sparse(z, zpos, {1, 2}, {{1, 0, 0}, {0, 1, 0}});
  const auto zv = vertices(load_triangle(z, zpos));
  EXPECT_EQ(zv[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(zv[1], glm::vec3(1, 0, 0));
  EXPECT_EQ(zv[2], glm::vec3(0, 1, 0));
}

TEST_F(GltfEncodings, BadSparseAccessorsAreRefused) {
  GltfWriter w;
  const int pos = w.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  make_sparse(w, pos, {3}, {{0, 5, 0}});
  expect_error([&] { load_triangle(w, pos); }, path(),
               "accessor 0 (POSITION): sparse index 3 is out of range");

  GltfWriter c;
  const int cpos = c.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  make_sparse(c, cpos, {0}, {{0, 5, 0}});
  c.doc["accessors"][cpos]["sparse"]["count"] = 2;  // values and indices are one element long
  expect_error([&] { load_triangle(c, cpos); }, path(),
               "sparse indices or values lie past the end of their bufferView");
}

TEST_F(GltfEncodings, TextureTransformAppliesTheSpecMatrixToTexcoords) {
  GltfWriter w;
  const int pos = w.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int uv = w.add_vec2({{0, 0}, {1, 0}, {0, 1}});
  const int tex = w.add_png_texture(hrpp::test::make_png(1, 1, {255, 255, 255, 255}));
  const float r = 0.5f;
  const json transform = {{"offset", {0.25, -0.5}}, {"rotation", r}, {"scale", {2, 3}}};
  const int mat = w.add_material(
      {{"pbrMetallicRoughness",
        {{"baseColorTexture",
          {{"index", tex}, {"extensions", {{"KHR_texture_transform", transform}}}}}}}});
  const Scene s = load_triangle(w, pos, -1, uv, mat);
  ASSERT_EQ(s.shading.size(), 1u);
  // translation(offset) * rotation * scale, the extension's GLSL (column-major mat3).
  auto expected = [&](glm::vec2 p) {
    const glm::vec2 q(2.0f * p.x, 3.0f * p.y);
    return glm::vec2(std::cos(r) * q.x - std::sin(r) * q.y + 0.25f,
                     std::sin(r) * q.x + std::cos(r) * q.y - 0.5f);
  };
  const glm::vec2 got[] = {s.shading[0].uv0, s.shading[0].uv1, s.shading[0].uv2};
  const glm::vec2 in[] = {{0, 0}, {1, 0}, {0, 1}};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(got[i].x, expected(in[i]).x, 1e-6f) << i;
    EXPECT_NEAR(got[i].y, expected(in[i]).y, 1e-6f) << i;
  }
}

// A material's textures share one set of texcoords: the first textured slot's transform moves
// them (here the metallic-roughness texture's, the base colour having none), and an emissive
// texture with another transform is named in a warning.
TEST_F(GltfEncodings, TextureTransformOfAMaterialIsItsFirstTexturesOne) {
  GltfWriter w;
  const int pos = w.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int uv = w.add_vec2({{0, 0}, {1, 0}, {0, 1}});
  const int tex = w.add_png_texture(hrpp::test::make_png(1, 1, {255, 255, 255, 255}));
  const auto info = [&](double offset) {
    return json{{"index", tex},
                {"extensions", {{"KHR_texture_transform", {{"offset", {offset, 0.0}}}}}}};
  };
  const int mat = w.add_material({{"pbrMetallicRoughness", {{"metallicRoughnessTexture", info(0.5)}}},
                                  {"emissiveFactor", {1, 1, 1}},
                                  {"emissiveTexture", info(0.25)}});
  const Scene s = load_triangle(w, pos, -1, uv, mat);
  ASSERT_EQ(s.shading.size(), 1u);
  EXPECT_EQ(s.shading[0].uv1, glm::vec2(1.5f, 0.0f));
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0], path() +
                               ": material 0: the emissiveTexture's KHR_texture_transform differs "
                               "from the metallicRoughnessTexture's, which is used");
}

TEST_F(GltfEncodings, VertexColoursArePackedPerVertex) {
  GltfWriter w;
  const int pos = w.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int rgb = w.add_vec3({{1, 0, 0}, {0, 0.5f, 2}, {-1, 0.2f, 1}});  // clamped to [0, 1]
  const int rgba = add_ints<std::uint8_t, 4>(w, {{255, 0, 0, 9}, {1, 2, 3, 9}, {0, 0, 255, 9}},
                                             kUnsignedByte, true);
  json a = GltfWriter::primitive(pos), b = a;
  a["attributes"]["COLOR_0"] = rgb;
  b["attributes"]["COLOR_0"] = rgba;
  w.add_scene({w.add_node(w.add_mesh({a, b, GltfWriter::primitive(pos)}))});
  const Scene s = load(w);
  ASSERT_EQ(s.shading.size(), 3u);
  EXPECT_TRUE(s.warnings.empty());
  // 0xBBGGRR, round(255 c): 0.5 -> 128, 0.2 -> 51.
  EXPECT_EQ(s.shading[0].c0, 0x0000FFu);
  EXPECT_EQ(s.shading[0].c1, 0xFF8000u);
  EXPECT_EQ(s.shading[0].c2, 0xFF3300u);
  EXPECT_EQ(s.shading[1].c0, 0x0000FFu);
  EXPECT_EQ(s.shading[1].c1, 0x030201u);
  EXPECT_EQ(s.shading[1].c2, 0xFF0000u);
  EXPECT_EQ(s.shading[2].c0, hrpp::kNoVertexColor);  // no COLOR_0
}

TEST_F(GltfEncodings, BadVertexColoursAreRefused) {
  GltfWriter w;
  const int pos = w.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int col = add_ints<std::int8_t, 3>(w, {{1, 0, 0}, {1, 0, 0}, {1, 0, 0}}, kByte, true);
  json prim = GltfWriter::primitive(pos);
  prim["attributes"]["COLOR_0"] = col;
  w.add_scene({w.add_node(w.add_mesh({prim}))});
  expect_error([&] { load(w); }, path(),
               "accessor 1 (COLOR_0) is normalized BYTE VEC3, expected FLOAT VEC3/VEC4 or "
               "normalized UNSIGNED_BYTE/UNSIGNED_SHORT VEC3/VEC4");
}

// A quad facing the default camera: base colour `base`, every vertex coloured `vertex`.
Scene coloured_quad(GltfFileTest& t, const std::string& name, glm::vec3 base, glm::vec3 vertex) {
  GltfWriter w;
  const int pos = w.add_vec3({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}});
  const int col = w.add_vec3({vertex, vertex, vertex, vertex});
  const int idx = w.add_indices({0, 1, 2, 0, 2, 3});
  const int mat = w.add_material(
      {{"pbrMetallicRoughness", {{"baseColorFactor", {base.x, base.y, base.z, 1.0}}}}});
  json prim = GltfWriter::primitive(pos, idx, mat);
  prim["attributes"]["COLOR_0"] = col;
  w.add_scene({w.add_node(w.add_mesh({prim}))});
  w.write(t.dir() / name);
  return load_scene((t.dir() / name).string());
}

// A manifest's material override replaces the object's vertex colours too; without one they stay.
TEST_F(GltfEncodings, ManifestMaterialOverridesDropVertexColours) {
  const glm::vec3 red(1, 0, 0);
  coloured_quad(*this, "q.glb", glm::vec3(1.0f), red);
  write_file(dir_ / "keep.scene.json", std::string(R"({"objects": [{"gltf": "q.glb"}]})"));
  write_file(dir_ / "over.scene.json",
             std::string(R"({"objects": [{"gltf": "q.glb", "material": {"type": "diffuse"}}]})"));
  EXPECT_EQ(load_scene(path("keep.scene.json")).shading[0].c0, 0x0000FFu);
  EXPECT_EQ(load_scene(path("over.scene.json")).shading[0].c0, kNoVertexColor);
}

// COLOR_0 multiplies the base colour: a red base colour under white vertex colours and a white
// one under red vertex colours render the same image (CPU reference; the device runs the same
// shading code, tests/cpu_render_test.cpp).
TEST_F(GltfEncodings, VertexColoursMultiplyTheBaseColour) {
  auto render = [](const Scene& s) { return cpu_image(s, 16, 2); };
  const glm::vec3 red(0.8f, 0.2f, 0.0f), white(1.0f);  // 8-bit exact: 204/255, 51/255
  const std::vector<float> by_material = render(coloured_quad(*this, "m.glb", red, white));
  const std::vector<float> by_vertex = render(coloured_quad(*this, "v.glb", white, red));
  const std::vector<float> plain = render(coloured_quad(*this, "w.glb", white, white));
  ASSERT_EQ(by_vertex.size(), by_material.size());
  float worst = 0.0f;  // interpolating equal vertex colours may round in the last bit
  for (std::size_t i = 0; i < by_vertex.size(); ++i) {
    worst = std::max(worst, std::abs(by_vertex[i] - by_material[i]));
  }
  EXPECT_LT(worst, 1e-5f);
  EXPECT_NE(by_vertex, plain);
}

}  // namespace

namespace {

GltfWriter triangle_with_extensions(const json& used, const json& required) {
  GltfWriter w;
  w.add_scene({w.add_node(w.add_triangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}))});
  if (!used.empty()) w.doc["extensionsUsed"] = used;
  if (!required.empty()) w.doc["extensionsRequired"] = required;
  return w;
}

TEST_F(GltfEncodings, RequiredExtensionsTheLoaderCannotHonourAreRefused) {
  triangle_with_extensions({"KHR_mesh_quantization", "KHR_texture_basisu"},
                           {"KHR_mesh_quantization", "KHR_texture_basisu"})
      .write(dir_ / "basisu.gltf");
  expect_error([&] { hrpp::load_gltf(dir_ / "basisu.gltf"); }, path("basisu.gltf"),
               "extension KHR_texture_basisu is required by the file but not supported");
}

TEST_F(GltfEncodings, UnknownUsedExtensionsAreIgnoredWithOneWarning) {
  const Scene s = load(triangle_with_extensions(
      {"KHR_mesh_quantization", "KHR_materials_sheen", "EXT_lights_ies"},
      {"KHR_mesh_quantization", "EXT_meshopt_compression", "KHR_draco_mesh_compression"}));
  EXPECT_EQ(s.triangles.size(), 1u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0],
            path() + ": extensions not supported, ignored: KHR_materials_sheen, EXT_lights_ies");
}

}  // namespace

// ---- the corpus: one mesh in each encoding (tests/gltf/make_encodings.sh) ----------------------
namespace {

const fs::path kCorpus = fs::path(HRPP_TEST_DATA_DIR) / "gltf_encodings";

// Every encoding of tests/data/gltf_encodings/ and its position quantization: the bits per
// component over the mesh's extent (gltfpack's and glTF-Transform's default: 14; Draco's default in
// glTF-Transform: 14; gltfpack's EXPONENTIAL filter keeps as many mantissa bits as the positions'
// precision, so FLOAT meshopt data is 14-bit too).
struct Encoded {
  const char* file;
  int position_bits;
};
constexpr Encoded kEncoded[] = {
    {"quantized_gltfpack.glb", 14}, {"quantized_transform.glb", 14}, {"meshopt_gltfpack.glb", 14},
    {"meshopt_float.glb", 14},      {"meshopt_transform.gltf", 14},  {"draco.glb", 14},
};

struct Bounds {
  glm::vec3 lo{3e38f}, hi{-3e38f};
};

Bounds bounds_of(const Scene& s) {
  Bounds b;
  for (const hrpp::Triangle& t : s.triangles) {
    for (const glm::vec3& v : {t.v0, t.v1, t.v2}) {
      b.lo = glm::min(b.lo, v);
      b.hi = glm::max(b.hi, v);
    }
  }
  return b;
}

glm::vec3 centroid(const hrpp::Triangle& t) { return (t.v0 + t.v1 + t.v2) / 3.0f; }

// The largest distance from a triangle of `s` to the nearest triangle (by centroid) of `ref`:
// the optimisers reorder triangles and vertices, so triangles are matched by position.
float farthest_match(const Scene& s, const Scene& ref) {
  float worst = 0.0f;
  for (const hrpp::Triangle& t : s.triangles) {
    float best = 3e38f;
    for (const hrpp::Triangle& r : ref.triangles) {
      best = std::min(best, glm::length(centroid(t) - centroid(r)));
    }
    worst = std::max(worst, best);
  }
  return worst;
}

TEST(GltfCorpus, EveryEncodingFlattensToThePlainTriangles) {
  const Scene plain = hrpp::load_gltf(kCorpus / "plain.glb");
  ASSERT_EQ(plain.triangles.size(), 992u);
  const Bounds pb = bounds_of(plain);
  const glm::vec3 extent = pb.hi - pb.lo;
  const float max_extent = std::max(extent.x, std::max(extent.y, extent.z));
  for (const Encoded& e : kEncoded) {
    SCOPED_TRACE(e.file);
    const Scene s = hrpp::load_gltf(kCorpus / e.file);
    EXPECT_TRUE(s.warnings.empty());
    ASSERT_EQ(s.triangles.size(), plain.triangles.size());
    // One quantization step: the extent over 2^bits - 1.
    const float step = max_extent / static_cast<float>((1 << e.position_bits) - 1);
    const Bounds b = bounds_of(s);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(b.lo[c], pb.lo[c], step) << "axis " << c;
      EXPECT_NEAR(b.hi[c], pb.hi[c], step) << "axis " << c;
    }
    EXPECT_LE(farthest_match(s, plain), step);
    for (const hrpp::TriangleShading& sh : s.shading) {  // every vertex has a unit normal
      EXPECT_NEAR(glm::length(sh.n0), 1.0f, 1e-4f);
    }
  }
}

// The renderer sees the same surfaces: the CPU reference image of each encoding at the plain
// file's camera and seed is the plain file's within relMSE 1e-4. Rendered without the files'
// specular layer (glTF's default), whose highlights magnify 8-bit normals' quantization where
// the surfaces are the question.
TEST(GltfCorpus, EveryEncodingRendersThePlainImage) {
  const Scene plain = hrpp::load_scene((kCorpus / "plain.glb").string());
  auto render = [](Scene s) {
    for (hrpp::Material& m : s.materials) m.specular = 0.0f;
    return cpu_image(s, 48, 4);
  };
  const std::vector<float> reference = render(plain);
  for (const Encoded& e : kEncoded) {
    Scene s = hrpp::load_scene((kCorpus / e.file).string());
    s.cameras = plain.cameras;  // the default camera frames the (slightly different) bounds
    const std::vector<float> image = render(s);
    ASSERT_EQ(image.size(), reference.size());
    double rel_mse = 0.0;
    for (std::size_t i = 0; i < image.size(); ++i) {
      const double d = image[i] - reference[i];
      rel_mse += d * d / (static_cast<double>(reference[i]) * reference[i] + 1e-2);
    }
    rel_mse /= static_cast<double>(image.size());
    EXPECT_LT(rel_mse, 1e-4) << e.file;
    std::printf("%s: relMSE %.3g\n", e.file, rel_mse);
  }
}

}  // namespace

// ---- corrupt compressed data: one line naming the extension, never a crash -------------------
namespace {

std::vector<std::uint8_t> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// A corpus GLB with its JSON edited by `edit`, written to dir/name.
fs::path edited_glb(const fs::path& dir, const std::string& name, const std::string& source,
                    const std::function<void(json&)>& edit) {
  const std::vector<std::uint8_t> bytes = read_bytes(kCorpus / source);
  std::uint32_t json_size = 0;
  std::memcpy(&json_size, bytes.data() + 12, 4);
  json doc = json::parse(bytes.begin() + 20, bytes.begin() + 20 + json_size);
  edit(doc);
  hrpp::test::write_file(dir / name, hrpp::replace_json(bytes, true, 20 + json_size, doc.dump()));
  return dir / name;
}

TEST_F(GltfEncodings, CorruptMeshoptDataIsRefusedNamingTheExtension) {
  const std::vector<std::pair<std::function<void(json&)>, std::string>> cases = {
      {[](json& d) {
         d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 40;
       },
       "bufferView 0 (EXT_meshopt_compression): corrupt ATTRIBUTES data"},
      {[](json& d) {
         d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["filter"] = "FOO";
       },
       "bufferView 0 (EXT_meshopt_compression): unknown filter \"FOO\""},
      {[](json& d) {
         d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteStride"] = 6;
       },
       "bufferView 0 (EXT_meshopt_compression): ATTRIBUTES byteStride"},
      {[](json& d) { d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = 1e9; },
       "cannot come from"},
      {[](json& d) { d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["buffer"] = 7; },
       "bufferView 0 (EXT_meshopt_compression): buffer 7 does not exist"},
  };
  for (const auto& [edit, message] : cases) {
    const fs::path f = edited_glb(dir_, "m.glb", "meshopt_gltfpack.glb", edit);
    expect_error([&] { hrpp::load_gltf(f); }, f.string(), message);
  }
}

TEST_F(GltfEncodings, CorruptDracoDataIsRefusedNamingTheExtension) {
  const std::string where = "mesh 0 primitive 0 (KHR_draco_mesh_compression)";
  const std::vector<std::pair<std::function<void(json&)>, std::string>> cases = {
      {[](json& d) { d["bufferViews"][0]["byteLength"] = 64; }, where + ": "},
      {[](json& d) { d["accessors"][0]["count"] = 3; }, where + ": accessor 0 has 3 indices"},
      {[](json& d) { d["accessors"][1]["count"] = 4; }, where + " POSITION: accessor 1 has 4"},
      {[](json& d) { d["accessors"][1]["type"] = "VEC2"; }, "does not match the Draco attribute"},
      {[](json& d) {
         d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]
          ["NORMAL"] = 9;
       },
       where + " NORMAL: Draco attribute 9 does not exist"},
  };
  for (const auto& [edit, message] : cases) {
    const fs::path f = edited_glb(dir_, "d.glb", "draco.glb", edit);
    expect_error([&] { hrpp::load_gltf(f); }, f.string(), message);
  }
}

}  // namespace

}  // namespace hrpp::test
