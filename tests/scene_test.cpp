// Scene stage: glTF loader, manifests, builtin Cornell box, load_scene dispatch, triangle dump.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "gltf_file_test.h"
#include "gltf_writer.h"
#include "scene/image_header.h"
#include "scene/load_scene.h"

namespace fs = std::filesystem;
using hrpp::Scene;
using hrpp::test::expect_error;
using hrpp::test::GltfWriter;
using nlohmann::json;

namespace {

constexpr float kEps = 1e-5f;

void expect_near(glm::vec3 a, glm::vec3 b, float eps = kEps) {
  EXPECT_NEAR(a.x, b.x, eps) << "x";
  EXPECT_NEAR(a.y, b.y, eps) << "y";
  EXPECT_NEAR(a.z, b.z, eps) << "z";
}

const std::vector<glm::vec3> kTri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
const std::vector<glm::vec3> kQuad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
const std::vector<std::uint32_t> kQuadIdx = {0, 1, 2, 0, 2, 3};

class SceneTest : public hrpp::test::GltfFileTest {};

GltfWriter one_triangle() {
  GltfWriter w;
  w.add_scene({w.add_node(w.add_triangles(kTri))});
  return w;
}

// ---- glTF: containers, transforms, hierarchy ---------------------------------------------------

TEST_F(SceneTest, GltfContainersLoadTheSameTriangle) {
  const GltfWriter w = one_triangle();
  w.write(dir_ / "a.glb");
  w.write(dir_ / "b.gltf", GltfWriter::Container::kGltfBin);
  w.write(dir_ / "c.gltf", GltfWriter::Container::kGltfDataUri);
  for (const char* name : {"a.glb", "b.gltf", "c.gltf"}) {
    const Scene s = hrpp::load_gltf(dir_ / name);
    ASSERT_EQ(s.triangles.size(), 1u) << name;
    EXPECT_EQ(s.name, name);
    expect_near(s.triangles[0].v1, {1, 0, 0});
    expect_near(s.triangles[0].v2, {0, 1, 0});
    EXPECT_EQ(s.shading[0].n0, glm::vec3(0.0f));  // no NORMAL attribute
  }
}

TEST_F(SceneTest, MatrixAndTrsGiveTheSameTransform) {
  // T(1,2,3) · Rz(90°) · S(2): (1,0,0) → (2,0,0) → (0,2,0) → (1,4,3).
  const glm::dquat q = glm::angleAxis(glm::radians(90.0), glm::dvec3(0, 0, 1));
  GltfWriter trs;
  const int mesh = trs.add_triangles(kTri);
  const int n = trs.add_node(mesh);
  trs.doc["nodes"][n]["translation"] = {1, 2, 3};
  trs.doc["nodes"][n]["rotation"] = {q.x, q.y, q.z, q.w};
  trs.doc["nodes"][n]["scale"] = {2, 2, 2};
  trs.add_scene({n});

  GltfWriter mat;
  const int mesh2 = mat.add_triangles(kTri);
  const int n2 = mat.add_node(mesh2);
  mat.doc["nodes"][n2]["matrix"] = {0, 2, 0, 0, -2, 0, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1};
  mat.add_scene({n2});

  const Scene a = load(trs, "trs.glb");
  const Scene b = load(mat, "matrix.glb");
  ASSERT_EQ(a.triangles.size(), 1u);
  ASSERT_EQ(b.triangles.size(), 1u);
  expect_near(a.triangles[0].v0, {1, 2, 3});
  expect_near(a.triangles[0].v1, {1, 4, 3});
  expect_near(a.triangles[0].v2, {-1, 2, 3});
  expect_near(b.triangles[0].v0, a.triangles[0].v0);
  expect_near(b.triangles[0].v1, a.triangles[0].v1);
  expect_near(b.triangles[0].v2, a.triangles[0].v2);
}

TEST_F(SceneTest, HierarchyComposesParentAndChild) {
  GltfWriter w;
  const int mesh = w.add_triangles(kTri);
  const int child = w.add_node(mesh);
  w.doc["nodes"][child]["translation"] = {0, 5, 0};
  w.doc["nodes"][child]["scale"] = {3, 3, 3};
  const int parent = w.add_node(-1, {child});
  w.doc["nodes"][parent]["translation"] = {10, 0, 0};
  w.doc["nodes"][parent]["scale"] = {1, 2, 1};
  w.add_scene({parent});
  const Scene s = load(w);
  ASSERT_EQ(s.triangles.size(), 1u);
  // parent(child(v)): (1,0,0) → (3,5,0) → (13,10,0)
  expect_near(s.triangles[0].v0, {10, 10, 0});
  expect_near(s.triangles[0].v1, {13, 10, 0});
  expect_near(s.triangles[0].v2, {10, 16, 0});
}

TEST_F(SceneTest, IndexTypesAndNonIndexedAgree) {
  std::vector<Scene> scenes;
  for (int type : {hrpp::test::kUnsignedByte, hrpp::test::kUnsignedShort,
                   hrpp::test::kUnsignedInt}) {
    GltfWriter w;
    w.add_scene({w.add_node(w.add_triangles(kQuad, kQuadIdx, -1, type))});
    scenes.push_back(load(w, "idx" + std::to_string(type) + ".glb"));
  }
  GltfWriter flat;
  std::vector<glm::vec3> unrolled;
  for (std::uint32_t i : kQuadIdx) unrolled.push_back(kQuad[i]);
  flat.add_scene({flat.add_node(flat.add_triangles(unrolled))});
  scenes.push_back(load(flat, "flat.glb"));
  for (const Scene& s : scenes) {
    ASSERT_EQ(s.triangles.size(), 2u);
    for (int t = 0; t < 2; ++t) {
      expect_near(s.triangles[t].v0, kQuad[kQuadIdx[3 * t]]);
      expect_near(s.triangles[t].v1, kQuad[kQuadIdx[3 * t + 1]]);
      expect_near(s.triangles[t].v2, kQuad[kQuadIdx[3 * t + 2]]);
    }
  }
}

TEST_F(SceneTest, InterleavedStridedAttributes) {
  // POSITION and NORMAL interleaved in one bufferView with byteStride 24.
  std::vector<float> data;
  for (const glm::vec3& p : kTri) data.insert(data.end(), {p.x, p.y, p.z, 0, 0, 1});
  GltfWriter w;
  const int bv = w.add_buffer_view(data.data(), data.size() * 4, 24);
  const int pos = w.add_accessor(bv, hrpp::test::kFloat, 3, "VEC3");
  const int nrm = w.add_accessor(bv, hrpp::test::kFloat, 3, "VEC3", 12);
  w.add_scene({w.add_node(w.add_mesh({GltfWriter::primitive(pos, -1, -1, nrm)}))});
  const Scene s = load(w);
  ASSERT_EQ(s.triangles.size(), 1u);
  expect_near(s.triangles[0].v2, {0, 1, 0});
  expect_near(s.shading[0].n1, {0, 0, 1});
}

TEST_F(SceneTest, NormalsUseInverseTransposeAndAreRenormalised) {
  GltfWriter w;
  const int pos = w.add_vec3(kTri);
  const glm::vec3 n = glm::normalize(glm::vec3(1, 1, 0));
  const int nrm = w.add_vec3({n, n, glm::vec3(0, 0, 1)});
  const int node = w.add_node(w.add_mesh({GltfWriter::primitive(pos, -1, -1, nrm)}));
  w.doc["nodes"][node]["scale"] = {2, 1, 1};
  w.add_scene({node});
  const Scene s = load(w);
  ASSERT_EQ(s.shading.size(), 1u);
  expect_near(s.shading[0].n0, glm::normalize(glm::vec3(0.5f, 1, 0)));
  expect_near(s.shading[0].n1, glm::normalize(glm::vec3(0.5f, 1, 0)));
  expect_near(s.shading[0].n2, {0, 0, 1});
  EXPECT_NEAR(glm::length(s.shading[0].n0), 1.0f, kEps);
}

TEST_F(SceneTest, TexcoordsFloatAndNormalizedU16) {
  GltfWriter w;
  const int pos = w.add_vec3(kTri);
  const int uvf = w.add_vec2({{0, 0}, {1, 0}, {0.25f, 0.75f}});
  const std::uint16_t raw[6] = {0, 0, 65535, 0, 0, 65535};
  const int bv = w.add_buffer_view(raw, sizeof raw);
  const int uvs = w.add_accessor(bv, hrpp::test::kUnsignedShort, 3, "VEC2", 0, true);
  w.add_scene({w.add_node(w.add_mesh({GltfWriter::primitive(pos, -1, -1, -1, uvf),
                                      GltfWriter::primitive(pos, -1, -1, -1, uvs)}))});
  const Scene s = load(w);
  ASSERT_EQ(s.shading.size(), 2u);
  EXPECT_EQ(s.shading[0].uv2, glm::vec2(0.25f, 0.75f));
  EXPECT_EQ(s.shading[1].uv1, glm::vec2(1.0f, 0.0f));
  EXPECT_EQ(s.shading[1].uv2, glm::vec2(0.0f, 1.0f));
}

// ---- glTF: materials ---------------------------------------------------------------------------

TEST_F(SceneTest, BaseColourFactorAndTexture) {
  const std::vector<std::uint8_t> pixels = {255, 0, 0, 255, 0, 255, 0, 255,
                                            0, 0, 255, 255, 10, 20, 30, 40};
  GltfWriter w;
  const int tex = w.add_png_texture(hrpp::test::make_png(2, 2, pixels));
  const int m0 = w.add_material({{"pbrMetallicRoughness",
                                  {{"baseColorFactor", {0.5, 0.25, 0.125, 1.0}},
                                   {"baseColorTexture", {{"index", tex}}}}}});
  const int m1 = w.add_material({{"pbrMetallicRoughness",
                                  {{"baseColorTexture", {{"index", tex}}}}}});
  const int m2 = w.add_material({{"name", "plain"},
                                  {"pbrMetallicRoughness", {{"baseColorFactor", {0.1, 0.2, 0.3, 1}}}}});
  const int pos = w.add_vec3(kTri);
  w.add_scene({w.add_node(w.add_mesh({GltfWriter::primitive(pos, -1, m0),
                                      GltfWriter::primitive(pos, -1, m1),
                                      GltfWriter::primitive(pos, -1, m2)}))});
  const Scene s = load(w);
  ASSERT_EQ(s.triangles.size(), 3u);
  ASSERT_EQ(s.textures.size(), 1u);  // decoded once for both materials
  EXPECT_EQ(s.textures[0].width, 2);
  EXPECT_EQ(s.textures[0].height, 2);
  EXPECT_EQ(s.textures[0].rgba, pixels);
  const auto& mat = s.materials;
  EXPECT_EQ(mat[s.shading[0].material].base_color, glm::vec3(0.5f, 0.25f, 0.125f));
  EXPECT_EQ(mat[s.shading[0].material].base_color_texture, 0);
  EXPECT_EQ(mat[s.shading[1].material].base_color, glm::vec3(1.0f));
  EXPECT_EQ(mat[s.shading[1].material].base_color_texture, 0);
  EXPECT_EQ(mat[s.shading[2].material].base_color_texture, -1);
  EXPECT_EQ(mat[s.shading[2].material].name, "plain");
  expect_near(mat[s.shading[2].material].base_color, {0.1f, 0.2f, 0.3f});
}

// metallicRoughnessTexture and emissiveTexture land in their slots with their texels as stored;
// an emissive texture without an emissiveFactor (default 0) emits nothing and is not decoded.
TEST_F(SceneTest, MetallicRoughnessAndEmissiveTextures) {
  const std::vector<std::uint8_t> mr_texel = {0, 128, 255, 255}, em_texel = {10, 20, 30, 255};
  GltfWriter w;
  const int mr = w.add_png_texture(hrpp::test::make_png(1, 1, mr_texel));
  const int em = w.add_png_texture(hrpp::test::make_png(1, 1, em_texel));
  const int m0 = w.add_material(
      {{"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", mr}}}}},
       {"emissiveFactor", {1.0, 0.5, 0.25}},
       {"emissiveTexture", {{"index", em}}}});
  const int m1 = w.add_material({{"emissiveTexture", {{"index", em}}}});
  const int pos = w.add_vec3(kTri);
  w.add_scene({w.add_node(w.add_mesh(
      {GltfWriter::primitive(pos, -1, m0), GltfWriter::primitive(pos, -1, m1)}))});
  const Scene s = load(w);
  ASSERT_EQ(s.triangles.size(), 2u);
  const hrpp::Material& a = s.materials[s.shading[0].material];
  const hrpp::Material& b = s.materials[s.shading[1].material];
  EXPECT_EQ(a.base_color_texture, -1);
  ASSERT_GE(a.metallic_roughness_texture, 0);
  ASSERT_GE(a.emissive_texture, 0);
  EXPECT_EQ(s.textures[a.metallic_roughness_texture].rgba, mr_texel);
  EXPECT_EQ(s.textures[a.emissive_texture].rgba, em_texel);
  EXPECT_EQ(a.emission, glm::vec3(1.0f, 0.5f, 0.25f));
  EXPECT_EQ(b.emissive_texture, -1);
  EXPECT_EQ(b.emission, glm::vec3(0.0f));
  EXPECT_EQ(s.textures.size(), 2u);
}

TEST_F(SceneTest, TextureFromExternalFileAndDataUri) {
  const std::vector<std::uint8_t> pixels = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  const std::vector<std::uint8_t> png = hrpp::test::make_png(3, 1, pixels);
  hrpp::test::write_file(dir_ / "tex.png", png);
  GltfWriter w;
  w.doc["images"] = {{{"uri", "tex.png"}}};
  w.doc["textures"] = {{{"source", 0}}};
  const int m = w.add_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  w.add_scene({w.add_node(w.add_triangles(kTri, {}, m))});
  const Scene s = load(w, "ext.gltf");
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].width, 3);
  EXPECT_EQ(s.textures[0].height, 1);
  EXPECT_EQ(s.textures[0].rgba, pixels);

  fs::remove(dir_ / "tex.png");
  expect_error([&] { hrpp::load_gltf(dir_ / "ext.gltf"); }, path("ext.gltf"));

  GltfWriter bad;  // an image that is not an image
  const std::vector<std::uint8_t> junk = {1, 2, 3, 4, 5, 6, 7, 8};
  const int tex = bad.add_png_texture(junk);
  const int bm = bad.add_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", tex}}}}}});
  bad.add_scene({bad.add_node(bad.add_triangles(kTri, {}, bm))});
  bad.write(dir_ / "junk.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "junk.glb"); }, path("junk.glb"), "image 0");
}

TEST_F(SceneTest, MetallicRoughnessEmissiveAndExtensions) {
  GltfWriter w;
  const int m = w.add_material(
      {{"pbrMetallicRoughness", {{"metallicFactor", 0.25}, {"roughnessFactor", 0.5}}},
       {"emissiveFactor", {1.0, 0.5, 0.25}},
       {"extensions",
        {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}},
         {"KHR_materials_ior", {{"ior", 1.33}}},
         {"KHR_materials_specular",
          {{"specularFactor", 0.5}, {"specularColorFactor", {1.0, 0.5, 0.25}}}},
         {"KHR_materials_transmission", {{"transmissionFactor", 0.75}}}}}});
  const int defaults = w.add_material(json::object());
  const int pos = w.add_vec3(kTri);
  w.add_scene({w.add_node(w.add_mesh({GltfWriter::primitive(pos, -1, m),
                                      GltfWriter::primitive(pos, -1, defaults),
                                      GltfWriter::primitive(pos)}))});
  const Scene s = load(w);
  ASSERT_EQ(s.triangles.size(), 3u);
  const hrpp::Material& a = s.materials[s.shading[0].material];
  EXPECT_FLOAT_EQ(a.metallic, 0.25f);
  EXPECT_FLOAT_EQ(a.roughness, 0.5f);
  expect_near(a.emission, {4.0f, 2.0f, 1.0f});
  EXPECT_FLOAT_EQ(a.ior, 1.33f);
  EXPECT_FLOAT_EQ(a.transmission, 0.75f);
  EXPECT_FLOAT_EQ(a.specular, 0.5f);
  expect_near(a.specular_color, {1.0f, 0.5f, 0.25f});
  const hrpp::Material& b = s.materials[s.shading[1].material];  // glTF defaults
  EXPECT_FLOAT_EQ(b.metallic, 1.0f);
  EXPECT_FLOAT_EQ(b.roughness, 1.0f);
  EXPECT_EQ(b.emission, glm::vec3(0.0f));
  EXPECT_FLOAT_EQ(b.ior, 1.5f);
  EXPECT_FLOAT_EQ(b.transmission, 0.0f);
  EXPECT_FLOAT_EQ(b.specular, 1.0f);  // a glTF dielectric has its specular layer
  EXPECT_EQ(b.specular_color, glm::vec3(1.0f));
  // No material: a default material, distinct from the file's.
  ASSERT_LT(s.shading[2].material, s.materials.size());
  EXPECT_GE(s.shading[2].material, 2u);
  EXPECT_EQ(s.materials[s.shading[2].material].emission, glm::vec3(0.0f));
}

// ---- glTF: cameras and lights -------------------------------------------------------------------

TEST_F(SceneTest, CameraFromNodeTransform) {
  GltfWriter w;
  const int mesh = w.add_triangles(kTri);
  const int cam = w.add_camera_perspective(0.5f, 1.5f);
  const int node = w.add_node();
  w.doc["nodes"][node]["camera"] = cam;
  w.doc["nodes"][node]["translation"] = {0, 1, 5};
  const glm::dquat q = glm::angleAxis(glm::radians(90.0), glm::dvec3(0, 1, 0));
  w.doc["nodes"][node]["rotation"] = {q.x, q.y, q.z, q.w};
  w.add_scene({w.add_node(mesh), node});
  const Scene s = load(w);
  ASSERT_EQ(s.cameras.size(), 1u);
  expect_near(s.cameras[0].position, {0, 1, 5});
  expect_near(s.cameras[0].forward, {-1, 0, 0});
  expect_near(s.cameras[0].up, {0, 1, 0});
  EXPECT_FLOAT_EQ(s.cameras[0].yfov, 0.5f);
  EXPECT_FLOAT_EQ(s.cameras[0].aspect, 1.5f);
}

TEST_F(SceneTest, PunctualPointAndSpotLights) {
  GltfWriter w;
  const int point = w.add_light({{"type", "point"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 8}});
  const int spot = w.add_light({{"type", "spot"},
                                {"intensity", 2},
                                {"range", 7},
                                {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.4}}}});
  const int sun = w.add_light({{"type", "directional"}, {"intensity", 3}});
  const int n0 = w.add_node(w.add_triangles(kTri));
  w.doc["nodes"][n0]["translation"] = {1, 2, 3};
  w.attach_light(n0, point);
  const int n1 = w.add_node();
  w.doc["nodes"][n1]["translation"] = {0, 4, 0};
  // Rotate -Z onto -Y: -90° about X.
  const glm::dquat q = glm::angleAxis(glm::radians(-90.0), glm::dvec3(1, 0, 0));
  w.doc["nodes"][n1]["rotation"] = {q.x, q.y, q.z, q.w};
  w.attach_light(n1, spot);
  const int n2 = w.add_node();
  w.attach_light(n2, sun);
  w.add_scene({n0, n1, n2});
  const Scene s = load(w);
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].type, hrpp::LightType::kPoint);
  expect_near(s.lights[0].color, {8, 4, 2});
  expect_near(s.lights[0].position, {1, 2, 3});
  EXPECT_EQ(s.lights[1].type, hrpp::LightType::kSpot);
  expect_near(s.lights[1].color, {2, 2, 2});
  expect_near(s.lights[1].position, {0, 4, 0});
  expect_near(s.lights[1].direction, {0, -1, 0});
  EXPECT_FLOAT_EQ(s.lights[1].inner_cone, 0.1f);
  EXPECT_FLOAT_EQ(s.lights[1].outer_cone, 0.4f);
  EXPECT_FLOAT_EQ(s.lights[1].range, 7.0f);
  EXPECT_EQ(s.lights[2].type, hrpp::LightType::kDirectional);
  expect_near(s.lights[2].direction, {0, 0, -1});
  EXPECT_FLOAT_EQ(s.lights[2].range, 0.0f);
}

// ---- glTF: triangle id order -------------------------------------------------------------------

TEST_F(SceneTest, TriangleIdOrderAcrossNodesAndPrimitives) {
  // Triangles tagged by their x offset: the expected id order is 0, 1, 2, 3, 4.
  auto tri_at = [](float x) {
    return std::vector<glm::vec3>{{x, 0, 0}, {x + 0.5f, 0, 0}, {x, 1, 0}};
  };
  GltfWriter w;
  const int p0 = w.add_vec3(tri_at(0)), p1 = w.add_vec3(tri_at(1));
  std::vector<glm::vec3> two = tri_at(2);
  for (const glm::vec3& v : tri_at(3)) two.push_back(v);
  const int p23 = w.add_vec3(two);
  const int idx = w.add_indices({0, 1, 2, 3, 4, 5}, hrpp::test::kUnsignedShort);
  const int mesh_a = w.add_mesh({GltfWriter::primitive(p0), GltfWriter::primitive(p1)});
  const int mesh_c = w.add_mesh({GltfWriter::primitive(p23, idx)});
  const int mesh_b = w.add_triangles(tri_at(4));
  const int unused = w.add_node(w.add_triangles(tri_at(99)));  // not in the scene
  (void)unused;
  const int grandchild = w.add_node(mesh_c);
  const int child = w.add_node(-1, {grandchild});
  const int a = w.add_node(mesh_a, {child});
  const int b = w.add_node(mesh_b);
  w.add_scene({a, b});
  const Scene s = load(w);
  ASSERT_EQ(s.triangles.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_FLOAT_EQ(s.triangles[i].v0.x, static_cast<float>(i)) << i;
}

TEST_F(SceneTest, DefaultSceneIsHonoured) {
  GltfWriter w;
  const int n0 = w.add_node(w.add_triangles(kTri));
  const int n1 = w.add_node(w.add_triangles(kQuad, kQuadIdx));
  w.add_scene({n0});
  w.add_scene({n1});
  w.doc["scene"] = 1;
  EXPECT_EQ(load(w).triangles.size(), 2u);
  w.doc.erase("scene");  // no default: scene 0
  EXPECT_EQ(load(w, "s0.glb").triangles.size(), 1u);
}

// ---- glTF: malformed inputs --------------------------------------------------------------------

TEST_F(SceneTest, ErrorMissingFile) {
  expect_error([&] { hrpp::load_gltf(dir_ / "nope.glb"); }, path("nope.glb"));
  expect_error([&] { hrpp::load_gltf(dir_ / "nope.gltf"); }, path("nope.gltf"));
  expect_error([&] { hrpp::load_scene(path("nope.glb")); }, path("nope.glb"));
}

TEST_F(SceneTest, ErrorMissingExternalBuffer) {
  const GltfWriter w = one_triangle();
  w.write(dir_ / "ext.gltf", GltfWriter::Container::kGltfBin);
  fs::remove(dir_ / "ext.bin");
  expect_error([&] { hrpp::load_gltf(dir_ / "ext.gltf"); }, path("ext.gltf"));
}

TEST_F(SceneTest, ErrorTruncatedGlb) {
  const std::vector<std::uint8_t> bytes = one_triangle().glb_bytes();
  for (std::size_t keep : {std::size_t{0}, std::size_t{7}, std::size_t{20}, bytes.size() / 2,
                           bytes.size() - 4}) {
    hrpp::test::write_file(dir_ / "t.glb",
                           std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + keep));
    expect_error([&] { hrpp::load_gltf(dir_ / "t.glb"); }, path("t.glb"));
  }
}

TEST_F(SceneTest, ErrorWrongMagic) {
  std::vector<std::uint8_t> bytes = one_triangle().glb_bytes();
  std::memcpy(bytes.data(), "glTX", 4);
  hrpp::test::write_file(dir_ / "m.glb", bytes);
  expect_error([&] { hrpp::load_gltf(dir_ / "m.glb"); }, path("m.glb"));
  hrpp::test::write_file(dir_ / "garbage.gltf", std::string("not json {"));
  expect_error([&] { hrpp::load_gltf(dir_ / "garbage.gltf"); }, path("garbage.gltf"));
}

TEST_F(SceneTest, ErrorAccessorOutOfRange) {
  GltfWriter w = one_triangle();
  w.doc["accessors"][0]["count"] = 4;  // 48 bytes in a 36-byte view and buffer
  w.write(dir_ / "oob.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "oob.glb"); }, path("oob.glb"), "accessor 0");

  GltfWriter v = one_triangle();
  v.doc["bufferViews"][0]["byteLength"] = 1000;
  v.write(dir_ / "bv.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "bv.glb"); }, path("bv.glb"));

  GltfWriter o = one_triangle();
  o.doc["accessors"][0]["byteOffset"] = 4;  // last element ends 4 bytes past the view
  o.write(dir_ / "off.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "off.glb"); }, path("off.glb"), "accessor 0");

  GltfWriter x = one_triangle();
  x.doc["accessors"][0]["count"] = 0x40000000;  // offset arithmetic must not overflow
  x.write(dir_ / "huge.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "huge.glb"); }, path("huge.glb"), "accessor 0");

  GltfWriter t = one_triangle();
  t.doc["accessors"][0]["componentType"] =
      hrpp::test::kUnsignedInt;  // not in KHR_mesh_quantization
  t.write(dir_ / "type.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "type.glb"); }, path("type.glb"), "POSITION");
}

TEST_F(SceneTest, IndexOutOfRangeIsAnErrorARaggedCountAWarning) {
  GltfWriter w;
  w.add_scene({w.add_node(w.add_triangles(kTri, {0, 1, 3}))});
  w.write(dir_ / "idx.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "idx.glb"); }, path("idx.glb"), "index 3");

  // A count not a multiple of 3 is a warning in the spec's validator: the whole triangles load.
  GltfWriter c;
  c.add_scene({c.add_node(c.add_triangles(kQuad, {0, 1, 2, 3}))});
  const Scene s = load(c, "count.glb");
  EXPECT_EQ(s.triangles.size(), 1u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0], path("count.glb") +
                               ": 1 TRIANGLES primitive with a vertex or index count not a "
                               "multiple of 3: the last 1 or 2 ignored");
}

TEST_F(SceneTest, ErrorNonFinitePositions) {
  for (float bad : {NAN, INFINITY, -INFINITY}) {
    GltfWriter w;
    w.add_triangles(kTri);  // mesh 0 / accessor 0: fine, unused
    std::vector<glm::vec3> p = kTri;
    p[2].y = bad;
    const int mesh = w.add_triangles(p);
    w.add_scene({w.add_node(mesh)});
    w.write(dir_ / "nan.glb");
    expect_error([&] { hrpp::load_gltf(dir_ / "nan.glb"); }, path("nan.glb"), "accessor 1");
  }
}

// A primitive of `positions` in `mode`, indexed when `indices` is not empty.
GltfWriter one_primitive(const std::vector<glm::vec3>& positions, int mode,
                         const std::vector<std::uint32_t>& indices = {}) {
  GltfWriter w;
  const int pos = w.add_vec3(positions);
  const int idx = indices.empty() ? -1 : w.add_indices(indices, hrpp::test::kUnsignedShort);
  w.add_scene({w.add_node(w.add_mesh({GltfWriter::primitive(pos, idx, -1, -1, -1, mode)}))});
  return w;
}

// Expects the scene's triangles to be exactly these vertices of `p`, in order.
void expect_triangles(const Scene& s, const std::vector<glm::vec3>& p,
                      const std::vector<std::array<int, 3>>& want) {
  ASSERT_EQ(s.triangles.size(), want.size());
  for (std::size_t t = 0; t < want.size(); ++t) {
    SCOPED_TRACE("triangle " + std::to_string(t));
    expect_near(s.triangles[t].v0, p[want[t][0]], 0.0f);
    expect_near(s.triangles[t].v1, p[want[t][1]], 0.0f);
    expect_near(s.triangles[t].v2, p[want[t][2]], 0.0f);
  }
}

// Strips and fans, plain and indexed, with the triangles the spec's order makes and the sign of
// their normals' z: every triangle of a strip or fan over a convex polygon winds the same way.
struct StripOrFan {
  int mode;
  std::vector<glm::vec3> positions;
  std::vector<std::uint32_t> indices;
  std::vector<std::array<int, 3>> triangles;
  float winding;
};

TEST_F(SceneTest, TriangleStripsAndFansUseTheSpecOrderAndWinding) {
  using hrpp::test::kModeTriangleFan, hrpp::test::kModeTriangleStrip;
  const std::vector<glm::vec3> zigzag = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}};
  const std::vector<glm::vec3> polygon = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}};
  const StripOrFan cases[] = {
      {kModeTriangleStrip, zigzag, {}, {{0, 1, 2}, {1, 3, 2}, {2, 3, 4}}, -1.0f},
      {kModeTriangleStrip, zigzag, {4, 3, 2, 1}, {{4, 3, 2}, {3, 1, 2}}, 1.0f},
      {kModeTriangleFan, polygon, {}, {{1, 2, 0}, {2, 3, 0}, {3, 4, 0}}, 1.0f},
      {kModeTriangleFan, polygon, {0, 1, 2, 3}, {{1, 2, 0}, {2, 3, 0}}, 1.0f},
  };
  for (const StripOrFan& c : cases) {
    SCOPED_TRACE("mode " + std::to_string(c.mode) + ", " + std::to_string(c.indices.size()) +
                 " indices");
    const Scene s = load(one_primitive(c.positions, c.mode, c.indices));
    expect_triangles(s, c.positions, c.triangles);
    for (const hrpp::Triangle& t : s.triangles) {
      EXPECT_GT(c.winding * glm::cross(t.v1 - t.v0, t.v2 - t.v0).z, 0.0f) << "winding flips";
    }
  }
}

TEST_F(SceneTest, ShortStripsAndFansHaveNoTriangles) {
  for (int mode : {hrpp::test::kModeTriangleStrip, hrpp::test::kModeTriangleFan}) {
    GltfWriter w;
    const int pos = w.add_vec3({{0, 0, 0}, {1, 0, 0}});
    w.add_scene({w.add_node(w.add_triangles(kTri)),
                 w.add_node(w.add_mesh({GltfWriter::primitive(pos, -1, -1, -1, -1, mode)}))});
    EXPECT_EQ(load(w).triangles.size(), 1u) << "mode " << mode;
  }
}

// Points and lines are skipped with one warning that counts them; the triangles stay.
TEST_F(SceneTest, PointsAndLinesAreSkippedWithOneWarning) {
  GltfWriter w;
  const int pos = w.add_vec3(kTri);
  std::vector<json> prims;
  for (int mode : {0, 1, 2, 3}) prims.push_back(GltfWriter::primitive(pos, -1, -1, -1, -1, mode));
  prims.push_back(GltfWriter::primitive(pos));
  const int mesh = w.add_mesh(prims);
  w.add_scene({w.add_node(mesh), w.add_node(mesh)});  // instanced twice: still 4 primitives
  const Scene s = load(w, "mixed.glb");
  EXPECT_EQ(s.triangles.size(), 2u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0],
            path("mixed.glb") + ": 4 points/lines primitives skipped (not surfaces)");
}

TEST_F(SceneTest, ErrorOnlyPointsAndLines) {
  for (int mode : {hrpp::test::kModePoints, hrpp::test::kModeLines}) {
    one_primitive(kTri, mode).write(dir_ / "mode.glb");
    expect_error([&] { hrpp::load_gltf(dir_ / "mode.glb"); }, path("mode.glb"),
                 "no triangles: only 1 points/lines primitive (not surfaces)");
  }
}

TEST_F(SceneTest, ErrorUnknownMode) {
  one_primitive(kTri, 7).write(dir_ / "mode.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "mode.glb"); }, path("mode.glb"),
               "mode 7 (unknown) is not supported");
}

TEST_F(SceneTest, ErrorZeroTriangles) {
  GltfWriter w;
  w.add_scene({w.add_node()});
  w.write(dir_ / "empty.glb");
  EXPECT_TRUE(hrpp::load_gltf(dir_ / "empty.glb").triangles.empty());
  expect_error([&] { hrpp::load_scene(path("empty.glb")); }, path("empty.glb"),
               "scene has no triangles");

  GltfWriter none;  // no scenes at all
  none.add_node(none.add_triangles(kTri));
  none.write(dir_ / "noscene.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "noscene.glb"); }, path("noscene.glb"), "no scene");
}

TEST_F(SceneTest, ErrorCyclicNodes) {
  GltfWriter w;
  const int mesh = w.add_triangles(kTri);
  const int a = w.add_node(mesh);
  const int b = w.add_node(-1, {a});
  w.doc["nodes"][a]["children"] = {b};
  w.add_scene({a});
  w.write(dir_ / "cycle.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "cycle.glb"); }, path("cycle.glb"), "cycle");

  GltfWriter self;
  const int n = self.add_node(self.add_triangles(kTri));
  self.doc["nodes"][n]["children"] = {n};
  self.add_scene({n});
  self.write(dir_ / "self.gltf");
  expect_error([&] { hrpp::load_gltf(dir_ / "self.gltf"); }, path("self.gltf"), "cycle");
}

TEST_F(SceneTest, ErrorDanglingReferences) {
  GltfWriter w = one_triangle();
  w.doc["scenes"][0]["nodes"] = {5};
  w.write(dir_ / "node.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "node.glb"); }, path("node.glb"));

  GltfWriter m = one_triangle();
  m.doc["meshes"][0]["primitives"][0]["material"] = 3;
  m.write(dir_ / "mat.glb");
  expect_error([&] { hrpp::load_gltf(dir_ / "mat.glb"); }, path("mat.glb"), "material 3");
}

// ---- builtin Cornell box -----------------------------------------------------------------------

TEST(BuiltinCornell, GeometryMaterialsLightCamera) {
  const Scene s = hrpp::builtin_cornell();
  EXPECT_EQ(s.name, "builtin:cornell");
  ASSERT_EQ(s.triangles.size(), 32u);
  ASSERT_EQ(s.shading.size(), 32u);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const auto& t : s.triangles) {
    EXPECT_FALSE(hrpp::is_degenerate(t));
    for (const glm::vec3& v : {t.v0, t.v1, t.v2}) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  }
  expect_near(lo, {0, 0, 0});
  expect_near(hi, {556.0f, 548.8f, 559.2f});
  // Exactly one emissive material, used by the two light triangles, plus one area light.
  int emissive_tris = 0;
  for (const auto& sh : s.shading) {
    ASSERT_LT(sh.material, s.materials.size());
    if (s.materials[sh.material].emission != glm::vec3(0.0f)) {
      ++emissive_tris;
      EXPECT_EQ(s.materials[sh.material].emission, glm::vec3(17, 12, 4));
    }
  }
  EXPECT_EQ(emissive_tris, 2);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, hrpp::LightType::kAreaQuad);
  EXPECT_EQ(s.lights[0].color, glm::vec3(17, 12, 4));
  EXPECT_LT(glm::cross(s.lights[0].edge_u, s.lights[0].edge_v).y, 0.0f);  // faces down
  EXPECT_NEAR(glm::length(glm::cross(s.lights[0].edge_u, s.lights[0].edge_v)), 130.0f * 105.0f,
              0.01f);
  // Every face looks into the box's free space: towards the camera side for walls (centre of
  // the box), away from the block centres for the blocks.
  const glm::vec3 centre(278, 274.4f, 279.6f);
  for (std::size_t i = 0; i < 12; ++i) {
    const auto& t = s.triangles[i];
    const glm::vec3 n = glm::cross(t.v1 - t.v0, t.v2 - t.v0);
    EXPECT_GT(glm::dot(n, centre - t.v0), 0.0f) << "triangle " << i;
  }
  for (std::size_t i = 12; i < 32; ++i) {
    const auto& t = s.triangles[i];
    const glm::vec3 block = i < 22 ? glm::vec3(186, 82.5f, 168.5f) : glm::vec3(368.5f, 165, 351.5f);
    const glm::vec3 n = glm::cross(t.v1 - t.v0, t.v2 - t.v0);
    EXPECT_LT(glm::dot(n, block - t.v0), 0.0f) << "triangle " << i;
  }
  // Red wall at x ≈ 556, green at x = 0.
  for (std::size_t i = 0; i < 32; ++i) {
    const std::string& name = s.materials[s.shading[i].material].name;
    if (name == "red") {
      EXPECT_GT(s.triangles[i].v0.x, 549.0f);
    }
    if (name == "green") {
      EXPECT_EQ(s.triangles[i].v0.x, 0.0f);
    }
  }
  ASSERT_EQ(s.cameras.size(), 1u);
  expect_near(s.cameras[0].position, {278, 273, -800});
  expect_near(s.cameras[0].forward, {0, 0, 1});
  EXPECT_NEAR(s.cameras[0].yfov, 2.0f * std::atan(0.0125f / 0.035f), 1e-6f);
}

// ---- load_scene, is_degenerate, triangle dump --------------------------------------------------

TEST_F(SceneTest, LoadSceneDispatchAndDefaultCamera) {
  const Scene cornell = hrpp::load_scene("builtin:cornell");
  EXPECT_EQ(cornell.triangles.size(), 32u);
  EXPECT_FALSE(cornell.default_camera);
  expect_error([] { hrpp::load_scene("builtin:nope"); }, "builtin:nope", "builtin:cornell");
  expect_error([] { hrpp::load_scene("no_such_scene_name"); }, "no_such_scene_name");
  expect_error([&] { hrpp::load_scene(path("x.obj")); }, path("x.obj"));

  GltfWriter w;
  w.add_scene({w.add_node(w.add_triangles({{-1, -2, -3}, {3, -2, -3}, {-1, 4, 1}}))});
  w.write(dir_ / "box.glb");
  const Scene s = hrpp::load_scene(path("box.glb"));
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_TRUE(s.default_camera);
  const hrpp::Camera& c = s.cameras[0];
  expect_near(c.forward, {0, 0, -1});
  expect_near(c.up, {0, 1, 0});
  EXPECT_NEAR(c.position.x, 1.0f, kEps);
  EXPECT_NEAR(c.position.y, 1.0f, kEps);
  EXPECT_NEAR(c.yfov, glm::radians(40.0f), 1e-6f);
  // The whole box is inside the vertical field of view from there.
  const float dist_front = c.position.z - 1.0f;
  EXPECT_GT(dist_front, 0.0f);
  EXPECT_LE(3.0f / dist_front, std::tan(glm::radians(20.0f)) + 1e-6f);
}

TEST(Degenerate, ZeroAreaAndNonFinite) {
  EXPECT_FALSE(hrpp::is_degenerate({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_TRUE(hrpp::is_degenerate({{0, 0, 0}, {0, 0, 0}, {0, 1, 0}}));
  EXPECT_TRUE(hrpp::is_degenerate({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}));
  EXPECT_TRUE(hrpp::is_degenerate({{0, 0, 0}, {1, 0, 0}, {0, NAN, 0}}));
  EXPECT_TRUE(hrpp::is_degenerate({{0, 0, 0}, {1, 0, 0}, {0, INFINITY, 0}}));
}

TEST_F(SceneTest, TriangleDumpRoundTrip) {
  const Scene s = hrpp::builtin_cornell();
  hrpp::write_triangle_dump(s, dir_ / "t.bin");
  std::ifstream in(dir_ / "t.bin", std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes.size(), s.triangles.size() * 36);
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    float f[9];
    std::memcpy(f, bytes.data() + 36 * i, 36);  // little-endian host
    EXPECT_EQ(glm::vec3(f[0], f[1], f[2]), s.triangles[i].v0);
    EXPECT_EQ(glm::vec3(f[3], f[4], f[5]), s.triangles[i].v1);
    EXPECT_EQ(glm::vec3(f[6], f[7], f[8]), s.triangles[i].v2);
  }
  expect_error([&] { hrpp::write_triangle_dump(s, dir_ / "no" / "dir" / "t.bin"); },
               path("no/dir/t.bin"));
}

// ---- manifests ----------------------------------------------------------------------------------

class ManifestTest : public SceneTest {
 protected:
  void SetUp() override {
    SceneTest::SetUp();
    fs::create_directories(dir_ / "meshes");
    // A 2×4×2 box-ish mesh: two triangles spanning x∈[-1,1], y∈[2,6], z∈[-1,1].
    GltfWriter w;
    const int m = w.add_material({{"name", "own"},
                                  {"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}}}});
    w.add_scene({w.add_node(w.add_triangles({{-1, 2, -1}, {1, 2, -1}, {1, 6, 1}, {-1, 6, 1}},
                                            {0, 1, 2, 0, 2, 3}, m))});
    w.write(dir_ / "meshes" / "part.glb");
  }
  Scene manifest(const json& j, const std::string& name = "m.scene.json") {
    hrpp::test::write_file(dir_ / name, j.dump(2));
    return hrpp::load_manifest(dir_ / name);
  }
  std::string manifest_error(const json& j, const std::string& fragment) {
    hrpp::test::write_file(dir_ / "bad.scene.json", j.dump(2));
    return expect_error([&] { hrpp::load_manifest(dir_ / "bad.scene.json"); },
                        path("bad.scene.json"), fragment);
  }
};

TEST_F(ManifestTest, FitTransformMaterialQuadLightsCameraAndIds) {
  const json j = {
      {"name", "demo"},
      {"objects",
       {{{"gltf", "meshes/part.glb"}},
        {{"gltf", "meshes/part.glb"},
         {"fit", {{"base", {10, 0, 0}}, {"size", 2.0}}},
         {"material", {{"type", "metal"}, {"color", {0.9, 0.8, 0.7}}, {"roughness", 0.3}}}},
        {{"gltf", "meshes/part.glb"},
         {"transform", {{"translate", {0, 0, 5}}, {"rotate_deg", {0, 90, 0}}, {"scale", 2}}},
         {"material", {{"type", "glass"}, {"ior", 1.4}}}},
        {{"quad", {{"corner", {-5, 0, -5}}, {"u", {10, 0, 0}}, {"v", {0, 0, 10}}}}},
        {{"quad", {{"corner", {0, 0, 0}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}}},
         {"transform", {{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 7, 8, 9, 1}}}},
         {"material", {{"type", "emissive"}, {"emission", {1, 2, 3}}, {"strength", 2}}}}}},
      {"lights",
       {{{"type", "area"}, {"corner", {-0.5, 3, -0.5}}, {"u", {1, 0, 0}}, {"v", {0, 0, 1}},
         {"radiance", {10, 10, 10}}},
        {{"type", "point"}, {"position", {2, 3, 2}}, {"intensity", {20, 20, 20}}},
        {{"type", "environment"}, {"radiance", {0.1, 0.1, 0.1}}}}},
      {"camera", {{"position", {0, 0.6, 3}}, {"target", {0, 0.6, 0}}, {"yfov_deg", 30}}}};
  const Scene s = manifest(j);
  EXPECT_EQ(s.name, "demo");
  // ids: part (2), fitted part (2), transformed part (2), floor quad (2), emissive quad (2),
  // area light quad (2).
  ASSERT_EQ(s.triangles.size(), 12u);
  ASSERT_EQ(s.shading.size(), 12u);
  // 0-1: as in the file, own material.
  expect_near(s.triangles[0].v0, {-1, 2, -1});
  EXPECT_EQ(s.materials[s.shading[0].material].name, "own");
  EXPECT_EQ(s.materials[s.shading[0].material].base_color, glm::vec3(1, 0, 0));
  // 2-3: fit: largest extent 4 → scale 0.5; bottom centre (0,2,0) → (10,0,0).
  expect_near(s.triangles[2].v0, {9.5f, 0, -0.5f});
  expect_near(s.triangles[2].v2, {10.5f, 2, 0.5f});
  const hrpp::Material& metal = s.materials[s.shading[2].material];
  EXPECT_FLOAT_EQ(metal.metallic, 1.0f);
  EXPECT_FLOAT_EQ(metal.roughness, 0.3f);
  expect_near(metal.base_color, {0.9f, 0.8f, 0.7f});
  // 4-5: scale 2, rotate 90° about y ((x,y,z) → (z,y,-x)), translate (0,0,5).
  // (-1,2,-1) → (-2,4,-2) → (-2,4,2) → (-2,4,7)
  expect_near(s.triangles[4].v0, {-2, 4, 7}, 1e-4f);
  const hrpp::Material& glass = s.materials[s.shading[4].material];
  EXPECT_FLOAT_EQ(glass.transmission, 1.0f);
  EXPECT_FLOAT_EQ(glass.ior, 1.4f);
  // 6-7: floor quad, default diffuse grey, facing u × v = (0,-100,0)?? u=(10,0,0), v=(0,0,10):
  // u × v = (0,-100,0): the README's example floor faces down; normals follow u × v.
  expect_near(s.triangles[6].v0, {-5, 0, -5});
  expect_near(s.triangles[6].v1, {5, 0, -5});
  expect_near(s.triangles[6].v2, {5, 0, 5});
  expect_near(s.triangles[7].v2, {-5, 0, 5});
  expect_near(s.shading[6].n0, {0, -1, 0});
  EXPECT_EQ(s.materials[s.shading[6].material].base_color, glm::vec3(0.8f));
  // 8-9: matrix transform and emissive material.
  expect_near(s.triangles[8].v0, {7, 8, 9});
  expect_near(s.materials[s.shading[8].material].emission, {2, 4, 6});
  // 10-11: the area light's quad, emissive with its radiance, facing u × v = (0,-1,0).
  expect_near(s.triangles[10].v0, {-0.5f, 3, -0.5f});
  expect_near(s.materials[s.shading[10].material].emission, {10, 10, 10});
  const glm::vec3 n = glm::cross(s.triangles[11].v1 - s.triangles[11].v0,
                                 s.triangles[11].v2 - s.triangles[11].v0);
  EXPECT_LT(n.y, 0.0f);
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].type, hrpp::LightType::kAreaQuad);
  expect_near(s.lights[0].edge_v, {0, 0, 1});
  EXPECT_EQ(s.lights[1].type, hrpp::LightType::kPoint);
  expect_near(s.lights[1].color, {20, 20, 20});
  EXPECT_EQ(s.lights[2].type, hrpp::LightType::kEnvironment);
  ASSERT_GE(s.cameras.size(), 1u);
  expect_near(s.cameras[0].position, {0, 0.6f, 3});
  expect_near(s.cameras[0].forward, {0, 0, -1});
  expect_near(s.cameras[0].up, {0, 1, 0});
  EXPECT_NEAR(s.cameras[0].yfov, glm::radians(30.0f), 1e-6f);
}

// Objects share a glTF file (loaded once): an object's fit, transform and material change its
// own copy only, and the scene's arrays are sized once (no slack left by growth).
TEST_F(ManifestTest, ObjectsSharingAFileGetTheirOwnCopies) {
  const json j = {
      {"objects",
       {{{"gltf", "meshes/part.glb"},
         {"transform", {{"translate", {0, 0, 5}}}},
         {"material", {{"type", "glass"}, {"ior", 1.4}}}},
        {{"gltf", "meshes/part.glb"}},
        {{"gltf", "meshes/part.glb"}, {"fit", {{"size", 1.0}}}}}},
      {"lights",
       {{{"type", "area"}, {"corner", {-0.5, 3, -0.5}}, {"u", {1, 0, 0}}, {"v", {0, 0, 1}},
         {"radiance", {10, 10, 10}}}}}};
  const Scene s = manifest(j);
  ASSERT_EQ(s.triangles.size(), 8u);
  EXPECT_EQ(s.triangles.capacity(), s.triangles.size());
  EXPECT_EQ(s.shading.capacity(), s.shading.size());
  expect_near(s.triangles[0].v0, {-1, 2, 4});
  EXPECT_FLOAT_EQ(s.materials[s.shading[0].material].transmission, 1.0f);
  expect_near(s.triangles[2].v0, {-1, 2, -1});  // as in the file
  EXPECT_EQ(s.materials[s.shading[2].material].name, "own");
  expect_near(s.triangles[4].v0, {-0.25f, 0, -0.25f});  // largest extent 4 → 1, base at 0
  EXPECT_EQ(s.materials[s.shading[4].material].name, "own");
}

// "specular" scales the file's specular layers (0: Lambertian); out of [0, 1] is an error.
TEST_F(ManifestTest, SpecularScalesTheFilesLayers) {
  const Scene s = manifest({{"objects",
                             {{{"gltf", "meshes/part.glb"}},
                              {{"gltf", "meshes/part.glb"}, {"specular", 0.0}}}}});
  EXPECT_FLOAT_EQ(s.materials[s.shading[0].material].specular, 1.0f);
  EXPECT_FLOAT_EQ(s.materials[s.shading[2].material].specular, 0.0f);
  manifest_error({{"objects", {{{"gltf", "meshes/part.glb"}, {"specular", 2.0}}}}},
                 "objects[0].specular");
}

TEST_F(ManifestTest, GltfCameraIsKeptAndLoadSceneFindsIt) {
  GltfWriter w;
  const int cam = w.add_camera_perspective(0.7f);
  const int cn = w.add_node();
  w.doc["nodes"][cn]["camera"] = cam;
  w.doc["nodes"][cn]["translation"] = {0, 0, 1};
  w.add_scene({w.add_node(w.add_triangles(kTri)), cn});
  w.write(dir_ / "meshes" / "cam.glb");
  const json j = {{"objects", {{{"gltf", "meshes/cam.glb"},
                                {"transform", {{"translate", {1, 0, 0}}}}}}}};
  hrpp::test::write_file(dir_ / "c.scene.json", j.dump());
  const Scene s = hrpp::load_scene(path("c.scene.json"));
  EXPECT_EQ(s.name, "c.scene.json");
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_FALSE(s.default_camera);
  expect_near(s.cameras[0].position, {1, 0, 1});
  EXPECT_FLOAT_EQ(s.cameras[0].yfov, 0.7f);
}

TEST_F(ManifestTest, ErrorBadJson) {
  hrpp::test::write_file(dir_ / "bad.scene.json", std::string("{\n  \"objects\": [\n  ,\n]}"));
  expect_error([&] { hrpp::load_manifest(dir_ / "bad.scene.json"); }, path("bad.scene.json"),
               "JSON syntax error at byte");
  expect_error([&] { hrpp::load_manifest(dir_ / "missing.scene.json"); },
               path("missing.scene.json"));
}

TEST_F(ManifestTest, ErrorUnknownKeysWrongTypesAndLengths) {
  const json quad = {{"corner", {0, 0, 0}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}};
  manifest_error({{"objects", json::array()}, {"lightz", json::array()}}, "lightz");
  manifest_error({{"objects", {{{"quad", quad}}, {{"quad", quad}}, {{"quad", quad},
                  {"material", {{"type", "diffuse"}, {"colour", {1, 1, 1}}}}}}}},
                 "objects[2].material.colour");
  manifest_error({{"objects", {{{"quad", quad}}, {{"quad", quad}}, {{"quad", quad},
                  {"material", {{"type", "plastic"}}}}}}},
                 "objects[2].material.type");
  manifest_error({{"objects", {{{"quad", {{"corner", {0, 0}}, {"u", {1, 0, 0}},
                                          {"v", {0, 1, 0}}}}}}}},
                 "objects[0].quad.corner");
  manifest_error({{"objects", {{{"quad", quad}, {"transform", {{"scale", "big"}}}}}}},
                 "objects[0].transform.scale");
  manifest_error({{"objects", {{{"quad", quad}, {"gltf", "meshes/part.glb"}}}}}, "objects[0]");
  manifest_error({{"objects", {{{"quad", quad}}}}, {"lights", {{{"type", "point"}}}}},
                 "lights[0].position");
  manifest_error({{"objects", {{{"quad", quad}}}}, {"camera", {{"position", {0, 0, 1}},
                                                              {"target", {0, 0, 0}},
                                                              {"yfov_deg", "wide"}}}},
                 "camera.yfov_deg");
  manifest_error({{"objects", 3}}, "objects");
}

TEST_F(ManifestTest, ErrorMissingMesh) {
  const std::string msg = manifest_error(
      {{"objects", {{{"gltf", "meshes/absent.glb"}}}}}, "absent.glb");
  EXPECT_EQ(msg.find("fetch-scenes"), std::string::npos);
  const std::string fetched = manifest_error(
      {{"objects", {{{"gltf", "fetched/dragon.glb"}}}}}, "(run tools/fetch-scenes.sh)");
  EXPECT_NE(fetched.find("fetched/dragon.glb"), std::string::npos);
  // A broken mesh names both files.
  hrpp::test::write_file(dir_ / "meshes" / "broken.glb", std::string("glTF"));
  const std::string broken =
      manifest_error({{"objects", {{{"gltf", "meshes/broken.glb"}}}}}, "broken.glb");
}

// ---- real meshes -------------------------------------------------------------------------------

TEST(RealMeshes, CommittedMeshesLoad) {
  const fs::path dir = fs::path(HRPP_TEST_SCENES_DIR) / "meshes";
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.path().extension() == ".glb" || e.path().extension() == ".gltf") {
      files.push_back(e.path());
    }
  }
  if (files.empty()) GTEST_SKIP() << "no meshes under " << dir;
  for (const fs::path& f : files) {
    const Scene s = hrpp::load_scene(f.string());
    EXPECT_GT(s.triangles.size(), 0u) << f;
    EXPECT_EQ(s.shading.size(), s.triangles.size()) << f;
    EXPECT_FALSE(s.cameras.empty()) << f;
    for (const auto& sh : s.shading) ASSERT_LT(sh.material, s.materials.size()) << f;
    for (const auto& m : s.materials) {
      ASSERT_LT(m.base_color_texture, static_cast<int>(s.textures.size())) << f;
    }
  }
}

TEST(RealMeshes, CommittedManifestsLoad) {
  const fs::path dir = fs::path(HRPP_TEST_SCENES_DIR);
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.size() > 11 && name.substr(name.size() - 11) == ".scene.json") files.push_back(e.path());
  }
  if (files.empty()) GTEST_SKIP() << "no manifests under " << dir;
  for (const fs::path& f : files) {
    try {
      const Scene s = hrpp::load_scene(f.string());
      EXPECT_GT(s.triangles.size(), 0u) << f;
    } catch (const hrpp::Error& e) {
      // Manifests may use meshes from fetched/ that this checkout has not fetched.
      if (std::string(e.what()).find("fetch-scenes") == std::string::npos) {
        ADD_FAILURE() << e.what();
      }
    }
  }
}

// ---- image headers (the texture size guard) ----------------------------------------------------

std::vector<std::uint8_t> bytes_of(std::initializer_list<int> v) {
  return std::vector<std::uint8_t>(v.begin(), v.end());
}

std::vector<std::uint8_t> operator+(std::vector<std::uint8_t> a,
                                    const std::vector<std::uint8_t>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// SOI, then segments before the frame header: APP0 (JFIF, 16 bytes), fill bytes, a standalone
// RST0, a DHT (C4: in the SOF range, but not a frame) and a DQT.
std::vector<std::uint8_t> jpeg_prefix() {
  return bytes_of({0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x10, 'J', 'F', 'I', 'F', 0, 1, 1, 0, 0, 1, 0, 1,
                   0, 0, 0xFF, 0xFF, 0xFF, 0xD0, 0xFF, 0xC4, 0x00, 0x04, 0x00, 0x00, 0xFF, 0xDB,
                   0x00, 0x03, 0x00});
}

// A frame header (marker, length 17, precision 8, height, width, 3 components).
std::vector<std::uint8_t> sof(int marker, int width, int height) {
  return bytes_of({0xFF, marker, 0x00, 0x11, 8, height >> 8, height & 0xFF, width >> 8,
                   width & 0xFF, 3, 1, 0x22, 0, 2, 0x11, 1, 3, 0x11, 1});
}

TEST(ImageHeader, JpegFrameHeaderAfterOtherSegments) {
  for (int marker : {0xC0, 0xC1, 0xC2, 0xC3, 0xC5, 0xC7, 0xC9, 0xCB, 0xCD, 0xCF}) {
    const auto h = hrpp::read_image_header(jpeg_prefix() + sof(marker, 60000, 300));
    ASSERT_TRUE(h.has_value()) << marker;
    EXPECT_EQ(h->format, "JPEG");
    EXPECT_EQ(h->width, 60000u);
    EXPECT_EQ(h->height, 300u);
  }
  const auto full = jpeg_prefix() + sof(0xC0, 65535, 65535);
  EXPECT_EQ(hrpp::read_image_header(full)->width, 65535u);
  // Cut anywhere before the end of the width: nothing to say (stb_image reports it).
  for (std::size_t n = 0; n < jpeg_prefix().size() + 9; ++n)
    EXPECT_FALSE(hrpp::read_image_header(std::span(full.data(), n)).has_value()) << n;
  // A scan before any frame header, a non-marker byte, not a JPEG.
  EXPECT_FALSE(hrpp::read_image_header(jpeg_prefix() + bytes_of({0xFF, 0xDA, 0, 2}) +
                                       sof(0xC0, 9, 9)).has_value());
  EXPECT_FALSE(hrpp::read_image_header(jpeg_prefix() + bytes_of({0x12}) + sof(0xC0, 9, 9))
                   .has_value());
  EXPECT_FALSE(hrpp::read_image_header(bytes_of({0xFF, 0xD9, 0xFF, 0xC0, 0, 0, 0, 0, 0, 0}))
                   .has_value());
}

TEST(ImageHeader, PngIhdr) {
  std::vector<std::uint8_t> rgba(3 * 2 * 4, 255);
  const auto h = hrpp::read_image_header(hrpp::test::make_png(3, 2, rgba));
  ASSERT_TRUE(h.has_value());
  EXPECT_EQ(h->format, "PNG");
  EXPECT_EQ(h->width, 3u);
  EXPECT_EQ(h->height, 2u);
}

// The lamborghini's textures (6 JPEGs, 2 PNGs): the headers give the sizes stb_image decodes.
TEST(ImageHeader, CommittedTexturesMatchTheDecoder) {
  const fs::path glb = fs::path(HRPP_TEST_SCENES_DIR) / "meshes" / "lamborghini_huracan.glb";
  std::ifstream in(glb, std::ios::binary);
  const std::vector<std::uint8_t> file((std::istreambuf_iterator<char>(in)), {});
  ASSERT_GT(file.size(), 20u);
  std::uint32_t json_length;
  std::memcpy(&json_length, file.data() + 12, 4);
  const json doc = json::parse(file.begin() + 20, file.begin() + 20 + json_length);
  const std::size_t bin = 20 + json_length + 8;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> from_headers, decoded;
  int jpegs = 0;
  for (const json& image : doc["images"]) {
    const json& view = doc["bufferViews"][image["bufferView"].get<int>()];
    const auto h = hrpp::read_image_header(
        std::span(file.data() + bin + view.value("byteOffset", 0), view["byteLength"]));
    ASSERT_TRUE(h.has_value());
    jpegs += h->format == "JPEG";
    from_headers.emplace_back(h->width, h->height);
  }
  for (const hrpp::Texture& t : hrpp::load_scene(glb.string()).textures)
    decoded.emplace_back(t.width, t.height);
  std::sort(from_headers.begin(), from_headers.end());
  std::sort(decoded.begin(), decoded.end());
  EXPECT_EQ(jpegs, 6);
  EXPECT_EQ(from_headers, decoded);
}

}  // namespace
