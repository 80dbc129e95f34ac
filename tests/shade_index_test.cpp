// host/render/shade_index.h: the indexed shading data (a ShadeIndex per triangle, shared
// ShadeVertex and ShadeAttributes records) gives every triangle the ShadeTriangle of the
// unindexed layout bit for bit. The witness is that layout, rebuilt here from the scene as
// make_render_scene built it before indexing (three copies of every corner, the light in the
// triangle). render_shade reads the same records through shade_triangle_of
// (tests/cpu_render_test.cpp: the device's images against the CPU reference's).
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/render_scene.h"
#include "scene/load_scene.h"
#include "test_scenes.h"

namespace hrpp {
namespace {

// The unindexed ShadeTriangle of triangle i (lights: 1 + the emissive triangles before it).
gpu::ShadeTriangle unindexed(const Scene& scene, const RenderScene& rs, std::size_t i,
                             std::uint32_t& next_light) {
  const Triangle& t = scene.triangles[i];
  const TriangleShading& s = scene.shading[i];
  gpu::ShadeTriangle g{};
  g.v0 = t.v0;
  g.v1 = t.v1;
  g.v2 = t.v2;
  g.material = s.material < scene.materials.size() ? s.material : 0;
  const glm::vec3 zero(0.0f);
  const bool normals = s.n0 != zero || s.n1 != zero || s.n2 != zero;
  const bool colors = s.c0 != kNoVertexColor || s.c1 != kNoVertexColor || s.c2 != kNoVertexColor;
  g.vertex_data = (normals ? HRPP_VERTEX_NORMALS : 0u) | (colors ? HRPP_VERTEX_COLORS : 0u);
  g.n0 = glm::vec4(s.n0, static_cast<float>(s.c0));
  g.n1 = glm::vec4(s.n1, static_cast<float>(s.c1));
  g.n2 = glm::vec4(s.n2, static_cast<float>(s.c2));
  g.uv01 = glm::vec4(s.uv0, s.uv1);
  g.uv2 = glm::vec4(s.uv2, 0.0f, 0.0f);
  const glm::vec3 e = rs.materials[g.material].emission;
  const bool emits = e.r > 0.0f || e.g > 0.0f || e.b > 0.0f;
  if (emits && !is_degenerate(t) && rs.emissive_triangles > 0 && !rs.lights.empty())
    g.light = next_light++;
  return g;
}

// Triangles whose indexed ShadeTriangle differs from the unindexed one in any byte.
std::size_t differing_triangles(const Scene& scene, const RenderScene& rs) {
  std::uint32_t next_light = 1;
  std::size_t differ = 0;
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const gpu::ShadeTriangle a = rs.shading.triangle(i);
    const gpu::ShadeTriangle b = unindexed(scene, rs, i, next_light);
    differ += std::memcmp(&a, &b, sizeof(a)) != 0;
  }
  return differ;
}

class ShadeIndexScenes : public testing::TestWithParam<std::string> {};

TEST_P(ShadeIndexScenes, EveryTriangleReadsItsUnindexedShadingBitForBit) {
  const Scene scene =
      load_scene((std::filesystem::path(HRPP_TEST_SCENES_DIR) / GetParam()).string());
  const RenderScene rs = make_render_scene(scene, DefaultLighting{});
  ASSERT_EQ(rs.shading.triangles.size(), scene.triangles.size());
  EXPECT_EQ(differing_triangles(scene, rs), 0u) << GetParam();
  EXPECT_LE(rs.shading.vertices.size(), 3 * scene.triangles.size());
  EXPECT_LE(rs.shading.attributes.size(), rs.shading.vertices.size());
}

// The committed manifests: lights of every kind, emissive triangles, textures, normals, uvs.
INSTANTIATE_TEST_SUITE_P(Manifests, ShadeIndexScenes,
                         testing::Values("cornell.scene.json", "bunny.scene.json",
                                         "bunny-complex.scene.json", "teapot.scene.json",
                                         "floor-panel.scene.json", "wall-lamp.scene.json",
                                         "lamborghini.scene.json", "meshes/cornell_box.glb"),
                         test::scene_param_name);

TEST(ShadeIndex, VertexColoursAndLightsSurviveIndexing) {
  Scene scene = load_scene("builtin:cornell");
  for (std::size_t i = 0; i < scene.shading.size(); i += 3) {
    scene.shading[i].c0 = 0x0000FFu + static_cast<std::uint32_t>(i);
    scene.shading[i].c2 = 0x00FF00u;
  }
  const RenderScene rs = make_render_scene(scene, DefaultLighting{});
  ASSERT_GT(rs.emissive_triangles, 0u);
  EXPECT_FALSE(rs.shading.attributes.empty());
  EXPECT_EQ(differing_triangles(scene, rs), 0u);
}

// A mesh's corners are shared: the bunny (positions and normals) stores about one vertex for
// two triangles, and the teapot (positions only) no attributes at all, nor does a mesh without
// them beside a floor with them (the floor's vertices are numbered first).
TEST(ShadeIndex, SharedCornersAreStoredOnce) {
  const Scene bunny = test::load_test_scene("meshes/mcguire_bunny.glb");
  const RenderScene b = make_render_scene(bunny, DefaultLighting{});
  EXPECT_LT(10 * b.shading.vertices.size(), 6 * bunny.triangles.size());
  EXPECT_EQ(b.shading.attributes.size(), b.shading.vertices.size());
  const Scene teapot = test::load_test_scene("meshes/utah_teapot.glb");
  const RenderScene t = make_render_scene(teapot, DefaultLighting{});
  EXPECT_LT(t.shading.vertices.size(), teapot.triangles.size());
  EXPECT_TRUE(t.shading.attributes.empty());
  EXPECT_EQ(differing_triangles(teapot, t), 0u);
  Scene both = teapot;
  for (const Triangle& tri : bunny.triangles) both.triangles.push_back(tri);
  for (const TriangleShading& s : bunny.shading) both.shading.push_back(s);
  const RenderScene m = make_render_scene(both, DefaultLighting{});
  EXPECT_EQ(m.shading.attributes.size(), b.shading.vertices.size());
  EXPECT_EQ(m.shading.vertices.size(), t.shading.vertices.size() + b.shading.vertices.size());
  EXPECT_EQ(differing_triangles(both, m), 0u);
}

// Equal positions with other normals, or another triangle's light, are other vertices.
TEST(ShadeIndex, CornersDifferingInAnyByteAreNotMerged) {
  Scene s = test::synthetic_scene({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                   {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                   {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
  s.shading[1].n0 = {0, 0, 1};
  s.shading[2].n0 = {-0.0f, 0, 0};  // -0 is not +0 in bytes
  const RenderScene rs = make_render_scene(s, DefaultLighting{});
  EXPECT_EQ(rs.shading.vertices.size(), 5u);
  EXPECT_EQ(differing_triangles(s, rs), 0u);
}

}  // namespace
}  // namespace hrpp
