// OBJ (with MTL) and PLY files and hrpp's checks around their readers (host/scene/obj_file.h,
// ply_file.h):
// every face form and encoding against hand-written triangles, the MTL mapping, the bad-input
// rules, and Debian's assimp-testmodels as a corpus that must load or be refused in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "common/error.h"
#include "scene/load_scene.h"
#include "scene/mtl_material.h"
#include "scene/polygon.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() {
  const fs::path d =
      fs::temp_directory_path() /
      ("hrpp_mesh_file_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::create_directories(d);
  return d;
}

fs::path write(const std::string& name, const std::string& bytes) {
  const fs::path p = temp_dir() / name;
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}

void expect_triangle(const Triangle& t, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  EXPECT_EQ(t.v0, a);
  EXPECT_EQ(t.v1, b);
  EXPECT_EQ(t.v2, c);
}

// Two triangles that tile the planar quad (a, b, c, d): corners of the quad, the quad's winding
// (normal n) and its area. assimp fans a quad from a concave corner, or one at 180° give or take
// a rounding, so which diagonal it takes is not fixed for a rectangle.
void expect_tiles_quad(const Triangle& t, const Triangle& u, const std::vector<glm::vec3>& quad,
                       float area, glm::vec3 n) {
  float sum = 0.0f;
  for (const Triangle& x : {t, u}) {
    for (const glm::vec3& v : {x.v0, x.v1, x.v2}) {
      EXPECT_NE(std::find(quad.begin(), quad.end(), v), quad.end());
    }
    const glm::vec3 c = glm::cross(x.v1 - x.v0, x.v2 - x.v0);
    EXPECT_GT(glm::dot(c, n), 0.0f);
    sum += 0.5f * glm::length(c);
  }
  EXPECT_FLOAT_EQ(sum, area);
}

// The one-line error load_scene gives for `file`; empty when it loads.
std::string error_of(const fs::path& file) {
  try {
    load_scene(file.string());
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const glm::vec3 k0(0, 0, 0), kX(1, 0, 0), kXY(1, 1, 0), kY(0, 1, 0);

TEST(Obj, EveryFaceFormNegativeIndicesAndPolygons) {
  write("forms.mtl", "newmtl red\nKd 0.8 0.1 0.1\n");
  const fs::path f = write("forms.obj",
                           "mtllib forms.mtl\no first\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                           "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nusemtl red\n"
                           "f 1 2 3\nf 1/1 2/2 3/3\nf 1//1 2//1 3//1\nf 1/1/1 2/2/1 3/3/1\n"
                           "f -4/-3/-1 -3/-2/-1 -2/-1/-1\ng second\nf 1 2 3 4\n");
  const Scene s = load_scene(f.string());
  ASSERT_EQ(s.triangles.size(), 7u);
  for (int i = 0; i < 5; ++i) expect_triangle(s.triangles[i], k0, kX, kXY);
  expect_tiles_quad(s.triangles[5], s.triangles[6], {k0, kX, kXY, kY}, 1.0f, {0, 0, 1});
  // vt (1, 1) is the image's top right in glTF's top-down rows: uv (1, 0).
  EXPECT_EQ(s.shading[1].uv2, glm::vec2(1, 0));
  EXPECT_EQ(s.shading[4].uv1, glm::vec2(1, 1));
  EXPECT_EQ(s.shading[3].n0, glm::vec3(0, 0, 1));
  EXPECT_EQ(s.materials[s.shading[0].material].name, "red");
  EXPECT_EQ(s.materials[s.shading[0].material].base_color, glm::vec3(0.8f, 0.1f, 0.1f));
  EXPECT_TRUE(s.default_camera);  // no camera in an OBJ: load_scene frames the bounds
}

// An L of six corners (area 3) is concave at (1, 1): a fan from corner 0 would cover the
// notch; ear clipping tiles the L exactly.
TEST(Obj, ConcavePolygonsAreEarClipped) {
  const std::vector<glm::vec3> l = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0},
                                    {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  const std::vector<std::uint32_t> t = triangulate_polygon(l);
  ASSERT_EQ(t.size(), 12u);
  float area = 0.0f;
  for (std::size_t i = 0; i < t.size(); i += 3) {
    const glm::vec3 c = glm::cross(l[t[i + 1]] - l[t[i]], l[t[i + 2]] - l[t[i]]);
    EXPECT_GT(c.z, 0.0f);  // wound as the polygon
    area += 0.5f * c.z;
  }
  EXPECT_FLOAT_EQ(area, 3.0f);
  // A convex pentagon is a fan from corner 0.
  const std::vector<std::uint32_t> f =
      triangulate_polygon({{0, 0, 0}, {1, 0, 0}, {1.5f, 1, 0}, {0.5f, 2, 0}, {-0.5f, 1, 0}});
  EXPECT_EQ(f, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4}));
}

TEST(Obj, MtlMapping) {
  write("m.mtl",
        "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1 2 3\nNs 100\n"
        "newmtl gold\nKd 0.1 0.1 0.1\nKs 0.9 0.7 0.3\nNs 1000\n"
        "newmtl glass\nKd 0.5 0.5 0.5\nNi 1.33\nillum 7\n");
  const fs::path f = write("m.obj",
                           "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n"
                           "usemtl gold\nf 1 2 3\nusemtl glass\nf 1 2 3\n");
  const Scene s = load_scene(f.string());
  ASSERT_EQ(s.triangles.size(), 3u);
  const Material& lamp = s.materials[s.shading[0].material];
  EXPECT_EQ(lamp.emission, glm::vec3(1, 2, 3));
  EXPECT_EQ(lamp.metallic, 0.0f);
  // Ns 100: alpha = sqrt(2 / 102), roughness = sqrt(alpha) = 0.37420...
  EXPECT_NEAR(lamp.roughness, 0.374203f, 1e-5f);
  const Material& gold = s.materials[s.shading[1].material];
  EXPECT_EQ(gold.metallic, 1.0f);  // Ks outweighs Kd: a metal of colour Ks
  EXPECT_EQ(gold.base_color, glm::vec3(0.9f, 0.7f, 0.3f));
  EXPECT_NEAR(gold.roughness, std::sqrt(std::sqrt(2.0f / 1002.0f)), 1e-6f);
  const Material& glass = s.materials[s.shading[2].material];
  EXPECT_EQ(glass.transmission, 1.0f);
  EXPECT_FLOAT_EQ(glass.ior, 1.33f);
}

TEST(Obj, DissolveIsWarnedAbout) {
  std::vector<std::string> warnings;
  MtlValues v;
  v.name = "veil";
  v.d = 0.5f;
  const Material m = material_from_mtl(v, warnings);
  EXPECT_EQ(m.transmission, 0.0f);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("veil"), std::string::npos);
}

// A PLY file of the given format: vertex x y z of `vtype`, faces as lists of (ctype, itype), an
// extra element that must be skipped.
std::string ply(const std::string& format, const std::string& vtype, const std::string& ctype,
                const std::string& itype, const std::string& body) {
  return "ply\nformat " + format + " 1.0\ncomment hand-written\nelement vertex 4\nproperty " +
         vtype + " x\nproperty " + vtype + " y\nproperty " + vtype + " z\nelement face 2\n" +
         "property list " + ctype + " " + itype + " vertex_indices\nelement edge 1\n" +
         "property int vertex1\nproperty int vertex2\nend_header\n" + body;
}

template <class T>
void put(std::string& out, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

// Vertices (0,0,0) (2,0,0) (2,3,0) (0,3,0); a triangle (0 1 2) and a quad (0 1 2 3); edge 0 1.
template <class V, class C, class I>
std::string ply_body(bool big) {
  std::string b;
  const int p[4][3] = {{0, 0, 0}, {2, 0, 0}, {2, 3, 0}, {0, 3, 0}};
  for (const auto& v : p) {
    for (int c : v) put<V>(b, static_cast<V>(c), big);
  }
  put<C>(b, 3, big);
  for (int k : {0, 1, 2}) put<I>(b, static_cast<I>(k), big);
  put<C>(b, 4, big);
  for (int k : {0, 1, 2, 3}) put<I>(b, static_cast<I>(k), big);
  put<std::int32_t>(b, 0, big);
  put<std::int32_t>(b, 1, big);
  return b;
}

void expect_ply_triangles(const fs::path& f) {
  const Scene s = load_scene(f.string());
  ASSERT_EQ(s.triangles.size(), 3u) << f;
  const glm::vec3 a(0, 0, 0), b(2, 0, 0), c(2, 3, 0), d(0, 3, 0);
  expect_triangle(s.triangles[0], a, b, c);
  expect_tiles_quad(s.triangles[1], s.triangles[2], {a, b, c, d}, 6.0f, {0, 0, 1});
}

TEST(Ply, AsciiBinaryLittleAndBigEndianAnyTypes) {
  const std::string ascii = "0 0 0\n2 0 0\n2 3 0\n0 3 0\n3 0 1 2\n4 0 1 2 3\n0 1\n";
  expect_ply_triangles(write("a.ply", ply("ascii", "float", "uchar", "int", ascii)));
  expect_ply_triangles(
      write("le_double.ply", ply("binary_little_endian", "double", "uchar", "uint",
                                 ply_body<double, std::uint8_t, std::uint32_t>(false))));
  expect_ply_triangles(
      write("be_short.ply", ply("binary_big_endian", "short", "int", "ushort",
                                ply_body<std::int16_t, std::int32_t, std::uint16_t>(true))));
  expect_ply_triangles(
      write("le_uchar.ply", ply("binary_little_endian", "uchar", "ushort", "short",
                                ply_body<std::uint8_t, std::uint16_t, std::int16_t>(false))));
  expect_ply_triangles(
      write("be_int.ply", ply("binary_big_endian", "int", "uchar", "int",
                              ply_body<std::int32_t, std::uint8_t, std::int32_t>(true))));
}

TEST(Ply, NormalsAndUvs) {
  std::string b;
  const float v[3][8] = {
      {0, 0, 0, 0, 0, 1, 0, 0}, {1, 0, 0, 0, 0, 1, 1, 0}, {0, 1, 0, 0, 0, 1, 0, 1}};
  for (const auto& row : v) {
    for (float x : row) put<float>(b, x, true);
  }
  put<std::uint8_t>(b, 3, true);
  for (int k : {0, 1, 2}) put<std::int32_t>(b, k, true);
  const fs::path f =
      write("nuv.ply",
            "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\n"
            "property float y\nproperty float z\nproperty float nx\nproperty float ny\n"
            "property float nz\nproperty float s\nproperty float t\nelement face 1\n"
            "property list uchar int vertex_indices\nend_header\n" +
                b);
  const Scene s = load_scene(f.string());
  ASSERT_EQ(s.triangles.size(), 1u);
  expect_triangle(s.triangles[0], k0, kX, kY);
  EXPECT_EQ(s.shading[0].n1, glm::vec3(0, 0, 1));
  EXPECT_EQ(s.shading[0].uv1, glm::vec2(1, 1));  // (s, t) = (1, 0): bottom right
  EXPECT_EQ(s.shading[0].uv2, glm::vec2(0, 0));  // (0, 1): top left
}

// A manifest places OBJ and PLY files as it places glTF ones ("mesh"), fit and material too.
TEST(MeshManifest, ObjAndPlyObjects) {
  write("unit.obj", "v 0 0 0\nv 2 0 0\nv 0 2 0\nf 1 2 3\n");
  write("unit.ply", ply("ascii", "float", "uchar", "int",
                        "0 0 0\n2 0 0\n2 3 0\n0 3 0\n3 0 1 2\n3 0 2 3\n0 1\n"));
  const fs::path m = write("meshes.scene.json",
                           R"({"objects": [{"mesh": "unit.obj", "transform": {"translate": [0, 0, 5]}},
                               {"mesh": "unit.ply", "fit": {"base": [0, 0, 0], "size": 1},
                                "material": {"type": "metal", "color": [0.9, 0.9, 0.9]}}]})");
  const Scene s = load_scene(m.string());
  ASSERT_EQ(s.triangles.size(), 3u);
  expect_triangle(s.triangles[0], {0, 0, 5}, {2, 0, 5}, {0, 2, 5});
  // fit: the largest extent (3, y) to 1, the bottom centre of the box to the origin
  EXPECT_NEAR(s.triangles[1].v2.y, 1.0f, 1e-6f);
  EXPECT_NEAR(s.triangles[1].v0.x, -1.0f / 3.0f, 1e-6f);
  EXPECT_EQ(s.materials[s.shading[1].material].metallic, 1.0f);
}

void expect_refused(const fs::path& f, const std::string& what) {
  const std::string e = error_of(f);
  EXPECT_NE(e.find(f.string()), std::string::npos) << e;
  EXPECT_NE(e.find(what), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST(BadMeshFiles, OneLineNamingTheFile) {
  const std::string good = ply_body<float, std::uint8_t, std::int32_t>(false);
  const std::string head_le = ply("binary_little_endian", "float", "uchar", "int", "");
  expect_refused(write("truncated.ply", head_le + good.substr(0, good.size() - 13)), "truncated");
  const std::string ascii_head = ply("ascii", "float", "uchar", "int", "");
  expect_refused(write("truncated_ascii.ply", ascii_head + "0 0 0\n2 0 0\n2 3 0\n0 3 0\n3 0 1"),
                 "truncated");
  expect_refused(
      write("out_of_range.ply", ascii_head + "0 0 0\n2 0 0\n2 3 0\n0 3 0\n3 0 1 7\n3 0 1 2\n0 1\n"),
      "vertex index 7 is out of range");
  expect_refused(
      write("nan.ply", ascii_head + "0 0 0\n2 0 0\nnan 3 0\n0 3 0\n3 0 1 2\n3 0 1 2\n0 1\n"),
      "non-finite");
  expect_refused(write("two.ply", ascii_head + "0 0 0\n2 0 0\n2 3 0\n0 3 0\n3 0 1 2\n2 0 1\n0 1\n"),
                 "fewer than three vertices");
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_refused(write("out_of_range.obj", tri + "f 1 2 9\n"),
                 "out_of_range.obj:4: vertex index 9");
  expect_refused(write("inf.obj", "v 0 0 0\nv 1 0 0\n# c\nv 0 inf 0\nf 1 2 3\n"),
                 "inf.obj:4: a coordinate that is not a finite number");
  expect_refused(write("two.obj", tri + "f 1 2 3\n\nf 1 2\n"),
                 "two.obj:6: a face of fewer than three");
  expect_refused(write("none.obj", tri), "no triangles");
}

// Every OBJ and PLY file of Debian's assimp-testmodels loads with triangles or is refused with
// one line naming it; none crashes.
TEST(MeshCorpus, AssimpTestModels) {
  const fs::path root = "/usr/share/assimp/models";
  std::error_code ec;
  if (!fs::exists(root, ec)) GTEST_SKIP() << "assimp-testmodels is not installed";
  int loaded = 0, refused = 0;
  for (const auto& e : fs::recursive_directory_iterator(root, ec)) {
    const std::string ext = e.path().extension().string();
    if (ext != ".obj" && ext != ".ply") continue;
    const std::string err = error_of(e.path());
    if (err.empty()) {
      ++loaded;
      continue;
    }
    ++refused;
    EXPECT_EQ(err.find('\n'), std::string::npos) << err;
    EXPECT_EQ(err.rfind(e.path().string(), 0), 0u) << err;
  }
  EXPECT_GE(loaded, 20) << refused << " refused";
}

}  // namespace
}  // namespace hrpp
