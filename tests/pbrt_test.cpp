// The pbrt-v4 reader (host/scene/pbrt_loader.h): transforms, attribute scopes, Include and
// Import, instancing and orientation against hand-computed world coordinates; pbrt's camera
// (left-handed: a known world point on a known pixel); lights and materials; and every bad-input
// rule of the format, as one line naming file and line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/error.h"
#include "render/render_params.h"
#include "scene/load_scene.h"
#include "scene/pbrt_loader.h"
#include "trace/ray_batches.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;

fs::path dir() {
  const fs::path d = fs::temp_directory_path() / "hrpp_pbrt_test";
  fs::create_directories(d);
  return d;
}

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = dir() / name;
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p;
}

Scene load(const std::string& name, const std::string& text) {
  return load_scene(write(name, text).string());
}

const char* const kTriangle =
    "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\n";

void expect_near(const glm::vec3& a, const glm::vec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-5f) << "x";
  EXPECT_NEAR(a.y, b.y, 1e-5f) << "y";
  EXPECT_NEAR(a.z, b.z, 1e-5f) << "z";
}

TEST(Pbrt, TransformsAgainstHandComputedWorldCoordinates) {
  const Scene s = load(
      "transforms.pbrt",
      std::string("WorldBegin\n") + "AttributeBegin\n Translate 1 2 3\n" + kTriangle +
          "AttributeEnd\n" + "AttributeBegin\n Scale 2 3 4\n" + kTriangle + "AttributeEnd\n" +
          "AttributeBegin\n Rotate 90 0 0 1\n" + kTriangle + "AttributeEnd\n" +
          // ctm = T(10,0,0) * S(2,2,2): a point p goes to 2p + (10,0,0)
          "AttributeBegin\n Translate 10 0 0 Scale 2 2 2\n" + kTriangle + "AttributeEnd\n" +
          // Transform: column-major 16 numbers, a translation by (5, 6, 7)
          "AttributeBegin\n Transform [1 0 0 0 0 1 0 0 0 0 1 0 5 6 7 1]\n" + kTriangle +
          "AttributeEnd\n" +
          "AttributeBegin\n Translate 1 0 0 ConcatTransform [2 0 0 0 0 2 0 0 0 0 2 0 0 0 0 1]\n" +
          kTriangle + "AttributeEnd\n" +
          "AttributeBegin\n Translate 9 9 9 CoordinateSystem \"nine\" Identity\n"
          " Translate 1 1 1 CoordSysTransform \"nine\"\n" +
          kTriangle + "AttributeEnd\n" + kTriangle);
  ASSERT_EQ(s.triangles.size(), 8u);
  expect_near(s.triangles[0].v0, {1, 2, 3});
  expect_near(s.triangles[0].v2, {1, 3, 3});
  expect_near(s.triangles[1].v1, {2, 0, 0});
  expect_near(s.triangles[1].v2, {0, 3, 0});
  expect_near(s.triangles[2].v1, {0, 1, 0});  // x axis turned 90° about z
  expect_near(s.triangles[2].v2, {-1, 0, 0});
  expect_near(s.triangles[3].v1, {12, 0, 0});
  expect_near(s.triangles[4].v1, {6, 6, 7});
  expect_near(s.triangles[5].v1, {3, 0, 0});  // T(1,0,0) * S(2): 2 · (1,0,0) + (1,0,0)
  expect_near(s.triangles[6].v0, {9, 9, 9});
  expect_near(s.triangles[7].v1, {1, 0, 0});  // AttributeEnd restored the identity
}

TEST(Pbrt, IncludeIsTextualImportIsScoped) {
  write("inc/moves.pbrt", "Translate 0 0 5\n");
  write("inc/imported.pbrt", std::string("Translate 0 0 7\n") + kTriangle);
  // Paths resolve against the main file's folder, also inside an included file.
  write("inc/nested.pbrt", "Include \"inc/moves.pbrt\"\n");
  const Scene s = load("include.pbrt", std::string("WorldBegin\nImport \"inc/imported.pbrt\"\n") +
                                           kTriangle + "Include \"inc/nested.pbrt\"\n" + kTriangle);
  ASSERT_EQ(s.triangles.size(), 3u);
  expect_near(s.triangles[0].v0, {0, 0, 7});
  expect_near(s.triangles[1].v0, {0, 0, 0});  // the Import's Translate stayed inside it
  expect_near(s.triangles[2].v0, {0, 0, 5});  // the Include's did not
}

TEST(Pbrt, InstancesFlattenWithTheirTransforms) {
  const Scene s = load(
      "instances.pbrt",
      std::string("WorldBegin\nObjectBegin \"tri\"\n Translate 1 0 0\n") + kTriangle +
          "ObjectEnd\n" + "AttributeBegin Translate 0 10 0 ObjectInstance \"tri\" AttributeEnd\n" +
          "AttributeBegin Scale 2 2 2 ObjectInstance \"tri\" AttributeEnd\n" + kTriangle);
  ASSERT_EQ(s.triangles.size(), 3u);  // the definition itself is not drawn
  expect_near(s.triangles[0].v0, {1, 10, 0});
  expect_near(s.triangles[0].v1, {2, 10, 0});
  expect_near(s.triangles[1].v0, {2, 0, 0});  // S(2) * T(1,0,0)
  expect_near(s.triangles[1].v2, {2, 2, 0});
  expect_near(s.triangles[2].v0, {0, 0, 0});  // ObjectEnd restored the transform
}

glm::vec3 geometric_normal(const Triangle& t) {
  return glm::normalize(glm::cross(t.v1 - t.v0, t.v2 - t.v0));
}

TEST(Pbrt, OrientationAndOneSidedAreaLights) {
  const Scene s = load("orientation.pbrt",
                       std::string("WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" "
                                   "\"rgb L\" [2 3 4] \"float scale\" 2\n") +
                           kTriangle + "ReverseOrientation\n" + kTriangle +
                           "AttributeEnd\nAttributeBegin Scale -1 1 1\n" + kTriangle +
                           "AttributeEnd\nAttributeBegin AreaLightSource \"diffuse\" \"bool "
                           "twosided\" true\n Shape \"disk\" \"float radius\" 2\nAttributeEnd\n");
  ASSERT_GE(s.triangles.size(), 4u);
  expect_near(geometric_normal(s.triangles[0]), {0, 0, 1});
  expect_near(geometric_normal(s.triangles[1]), {0, 0, -1});  // ReverseOrientation
  expect_near(geometric_normal(s.triangles[2]), {0, 0, 1});   // a mirror keeps pbrt's side
  const Material& lamp = s.materials[s.shading[0].material];
  EXPECT_EQ(lamp.emission, glm::vec3(4, 6, 8));
  EXPECT_FALSE(lamp.two_sided_emission);  // pbrt's default
  EXPECT_EQ(s.materials[s.shading[2].material].emission, glm::vec3(0));
  const Material& disk = s.materials[s.shading.back().material];
  EXPECT_TRUE(disk.two_sided_emission);
  EXPECT_EQ(disk.emission, glm::vec3(1));
  expect_near(geometric_normal(s.triangles.back()), {0, 0, 1});  // pbrt's disk faces +z
}

// A pbrt camera at the origin looking down +z with +y up, fov 90 on a 100x100 film. pbrt's
// screen x is camera x = up × dir = +x, so the world point (1.02, 0.5, 2) projects to screen
// (0.51, 0.25), raster (75.5, 37.5): the centre of pixel (75, 37). A right-handed camera with
// the same forward and up would put it at column 24.
TEST(Pbrt, CameraPutsAKnownPointOnAKnownPixel) {
  const Scene s =
      load("camera.pbrt",
           std::string("LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" 90\n"
                       "Film \"rgb\" \"integer xresolution\" 100 \"integer yresolution\" 100\n"
                       "Sampler \"halton\" \"integer pixelsamples\" 7\nWorldBegin\n") +
               kTriangle);
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_FALSE(s.default_camera);
  EXPECT_EQ(s.film_width, 100u);
  EXPECT_EQ(s.film_height, 100u);
  EXPECT_EQ(s.film_spp, 7u);
  const Camera& c = s.cameras[0];
  EXPECT_TRUE(c.mirrored);
  EXPECT_NEAR(c.yfov, glm::radians(90.0f), 1e-6f);
  const std::vector<gpu::Ray> rays = make_primary_rays(c, 100, 100, false, 0);
  const glm::vec3 to = glm::normalize(glm::vec3(1.02f, 0.5f, 2.0f) - c.position);
  std::size_t best = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (glm::dot(rays[i].dir, to) > glm::dot(rays[best].dir, to)) best = i;
  }
  EXPECT_EQ(best % 100, 75u);
  EXPECT_EQ(best / 100, 37u);
  // The renderers' camera (render_params) agrees: image right is world +x here.
  RenderConfig cfg;
  const gpu::RenderParams p = make_render_params(cfg, c, RenderScene{}, 0);
  expect_near(glm::vec3(p.cam_right), {1, 0, 0});
  expect_near(glm::vec3(p.cam_up), {0, 1, 0});
}

TEST(Pbrt, FovSpansTheShorterSide) {
  const Scene s =
      load("tall.pbrt", std::string("Camera \"perspective\" \"float fov\" 60\nFilm \"rgb\" "
                                    "\"integer xresolution\" 50 \"integer yresolution\" 100\n"
                                    "WorldBegin\n") +
                            kTriangle);
  // The width is the shorter side: tan(yfov / 2) = tan(30°) / (50 / 100).
  EXPECT_NEAR(std::tan(0.5f * s.cameras[0].yfov), std::tan(glm::radians(30.0f)) * 2.0f, 1e-5f);
}

TEST(Pbrt, LightsAndMaterials) {
  const Scene s =
      load("lights.pbrt",
           std::string(
               "WorldBegin\n"
               "LightSource \"point\" \"point3 from\" [1 2 3] \"rgb I\" [1 2 3] \"float scale\" 2\n"
               "LightSource \"distant\" \"point3 from\" [0 0 0] \"point3 to\" [0 0 -1] \"rgb L\" "
               "[3 3 3]\n"
               "LightSource \"infinite\" \"rgb L\" [0.1 0.2 0.3]\n"
               "LightSource \"spot\" \"point3 from\" [0 5 0] \"point3 to\" [0 0 0] \"float "
               "coneangle\" 20 \"float conedelta\" 5\n"
               "MakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" "
               "\"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\" \"float roughness\" 0.01\n"
               "Material \"dielectric\" \"float eta\" 1.33\n") +
               kTriangle + "NamedMaterial \"gold\"\n" + kTriangle +
               "Material \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]\n" + kTriangle +
               "Material \"coateddiffuse\" \"float roughness\" 0.04 \"float eta\" 1.7\n" +
               kTriangle);
  ASSERT_EQ(s.lights.size(), 4u);
  EXPECT_EQ(s.lights[0].type, LightType::kPoint);
  expect_near(s.lights[0].position, {1, 2, 3});
  expect_near(s.lights[0].color, {2, 4, 6});
  EXPECT_EQ(s.lights[1].type, LightType::kDirectional);
  expect_near(s.lights[1].direction, {0, 0, -1});
  EXPECT_EQ(s.lights[2].type, LightType::kEnvironment);
  EXPECT_EQ(s.lights[3].type, LightType::kSpot);
  EXPECT_NEAR(s.lights[3].outer_cone, glm::radians(20.0f), 1e-6f);
  EXPECT_NEAR(s.lights[3].inner_cone, glm::radians(15.0f), 1e-6f);
  const Material& glass = s.materials[s.shading[0].material];
  EXPECT_EQ(glass.transmission, 1.0f);
  EXPECT_FLOAT_EQ(glass.ior, 1.33f);
  const Material& gold = s.materials[s.shading[1].material];
  EXPECT_EQ(gold.metallic, 1.0f);
  EXPECT_GT(gold.base_color.x, gold.base_color.z);  // yellow
  // pbrt's roughness 0.01, remapped: alpha = sqrt(0.01) = 0.1; hrpp's roughness sqrt(alpha)
  EXPECT_NEAR(gold.roughness, std::sqrt(0.1f), 1e-6f);
  EXPECT_EQ(s.materials[s.shading[2].material].base_color, glm::vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(s.materials[s.shading[2].material].specular, 0.0f);  // diffuse: Lambertian
  // coateddiffuse: its coat as the specular layer, roughness remapped as above (alpha 0.2).
  const Material& coated = s.materials[s.shading[3].material];
  EXPECT_EQ(coated.specular, 1.0f);
  EXPECT_FLOAT_EQ(coated.ior, 1.7f);
  EXPECT_NEAR(coated.roughness, std::sqrt(0.2f), 1e-6f);
  EXPECT_EQ(coated.base_color, glm::vec3(0.5f));  // pbrt's default reflectance
}

TEST(Pbrt, ShapesOtherThanMeshes) {
  const Scene s = load("shapes.pbrt",
                       "WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n"
                       "Shape \"loopsubdiv\" \"integer levels\" 1 \"point3 P\" [0 0 0 1 0 0 0 1 0] "
                       "\"integer indices\" [0 1 2]\n"
                       "Shape \"sphere\" \"float radius\" 2\nShape \"cylinder\"\n");
  // pbrt's split of a patch (q0 q1 q2 q3): (q0, q1, q3) and (q0, q3, q2).
  expect_near(s.triangles[0].v2, {1, 1, 0});
  expect_near(s.triangles[1].v1, {1, 1, 0});
  expect_near(s.triangles[1].v2, {0, 1, 0});
  EXPECT_GT(s.triangles.size(), 2u + 4u + 1000u);
}

void expect_error(const std::string& name, const std::string& text, const std::string& what) {
  const fs::path f = write(name, text);
  try {
    load_scene(f.string());
    ADD_FAILURE() << name << " loaded";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(what), std::string::npos) << m;
    EXPECT_NE(m.find(name), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(BadPbrt, OneLineNamingFileAndLine) {
  expect_error("unknown.pbrt", "WorldBegin\nFrobnicate 1 2\n",
               "unknown.pbrt:2: unknown directive \"Frobnicate\"");
  expect_error("unbalanced.pbrt", "WorldBegin\nAttributeEnd\n",
               "unbalanced.pbrt:2: AttributeEnd without");
  expect_error("missing_include.pbrt", "Include \"nowhere.pbrt\"\n", "nowhere.pbrt: no such file");
  expect_error("self.pbrt", "Include \"self.pbrt\"\n", "includes itself");
  expect_error("string.pbrt", "WorldBegin\nShape \"trianglemesh\n",
               "string.pbrt:2: unterminated string");
  expect_error("nonmanifold.pbrt",
               "Shape \"loopsubdiv\" \"point3 P\" [0 0 0 1 0 0 0 1 0 0 -1 0 0 0 1] "
               "\"integer indices\" [0 1 2 1 0 3 0 1 4]\n",
               "non-manifold edge");
  expect_error(
      "short_face.pbrt",
      "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2 0]\n",
      "fewer than three vertices");
  expect_error(
      "range.pbrt",
      "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 5]\n",
      "out of range");
  expect_error("nan.pbrt", "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 nan 1 0]\n",
               "non-finite");
  expect_error("shape.pbrt", "Shape \"curve\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 1]\n",
               "shape.pbrt:1: Shape \"curve\" is not supported");
  expect_error("param.pbrt", "Shape \"sphere\" \"float radiu\" 2\n", "\"float radiu\" is not one");
  expect_error("number.pbrt", "Translate 1 two 3\n", "number.pbrt:1: Translate: expected a number");
}

// The paper's Killeroo Simple, when tools/fetch-scenes.sh has copied it: two Killeroos of
// 33,264 triangles after one level of Loop subdivision, two quads and the sphere light.
TEST(Killeroo, SimpleHasThePapersTriangles) {
  const fs::path f = fs::path(HRPP_TEST_SCENES_DIR) / "fetched/killeroos/killeroo-simple.pbrt";
  std::error_code ec;
  if (!fs::exists(f, ec)) GTEST_SKIP() << "tools/fetch-scenes.sh has not fetched the Killeroos";
  const Scene s = load_scene("killeroo-simple");
  std::size_t lamp = 0;
  for (const TriangleShading& t : s.shading)
    lamp += s.materials[t.material].emission != glm::vec3(0);
  EXPECT_EQ(s.triangles.size() - lamp, 2u * 33264u + 4u);
  EXPECT_TRUE(s.cameras[0].mirrored);
  EXPECT_EQ(s.film_width, 700u);
  EXPECT_EQ(s.film_spp, 256u);
}

}  // namespace
}  // namespace hrpp
