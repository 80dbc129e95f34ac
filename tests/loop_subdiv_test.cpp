// host/scene/loop_subdiv: pbrt-v4's Loop subdivision against positions worked out by hand from
// the masks (loop_subdiv.h), the vertex and triangle order, the orientation of pbrt's limit
// normals, triangle counts, and the refusals of bad control meshes.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.h"
#include "scene/loop_subdiv.h"

namespace hrpp {
namespace {

using Indices = std::vector<std::uint32_t>;
using Points = std::vector<glm::vec3>;

constexpr float kTolerance = 1e-5f;

void expect_near(const glm::vec3& actual, const glm::vec3& expected, const std::string& what) {
  EXPECT_NEAR(actual.x, expected.x, kTolerance) << what;
  EXPECT_NEAR(actual.y, expected.y, kTolerance) << what;
  EXPECT_NEAR(actual.z, expected.z, kTolerance) << what;
}

void expect_positions(const IndexedMesh& mesh, const Points& expected) {
  ASSERT_EQ(mesh.positions.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    expect_near(mesh.positions[i], expected[i], "vertex " + std::to_string(i));
  }
}

// Every corner's normal is on the side the triangle is counter-clockwise from.
void expect_winding_follows_normals(const IndexedMesh& mesh) {
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const glm::vec3 a = mesh.positions[mesh.indices[3 * t]];
    const glm::vec3 b = mesh.positions[mesh.indices[3 * t + 1]];
    const glm::vec3 c = mesh.positions[mesh.indices[3 * t + 2]];
    const glm::vec3 ng = glm::cross(b - a, c - a);
    for (int k = 0; k < 3; ++k) {
      EXPECT_GT(glm::dot(ng, mesh.normals[mesh.indices[3 * t + k]]), 0.0f) << "triangle " << t;
    }
  }
}

std::string error_of(const Points& points, const Indices& indices, int levels) {
  try {
    loop_subdivide(points, indices, levels, "scene.pbrt:7");
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// The unit right triangle a = (0,0,0), b = (1,0,0), c = (0,1,0): three boundary vertices of
// valence 2 (one face, plus one).
const Points kTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

TEST(LoopSubdiv, SingleTriangleLevel0IsPushedToTheLimit) {
  // Boundary limit: 3/5 self + 1/5 each boundary neighbour.
  //   a: 3/5 (0,0) + 1/5 (1,0) + 1/5 (0,1) = (0.2, 0.2)
  //   b: 3/5 (1,0) + 1/5 (0,1) + 1/5 (0,0) = (0.6, 0.2)
  //   c: 3/5 (0,1) + 1/5 (0,0) + 1/5 (1,0) = (0.2, 0.6)
  const IndexedMesh mesh = loop_subdivide(kTriangle, {0, 1, 2}, 0, "t");
  expect_positions(mesh, {{0.2f, 0.2f, 0}, {0.6f, 0.2f, 0}, {0.2f, 0.6f, 0}});
  // pbrt's triangle (0, 1, 2) comes back as (0, 2, 1).
  EXPECT_EQ(mesh.indices, (Indices{0, 2, 1}));
  // Normals, valence-2 boundary: ring r = (next corner, previous corner); S = r1 - r0,
  // T = r0 + r1 - 2p.
  //   a: S = c' - b' = (-0.4, 0.4, 0), T = b' + c' - 2a' = (0.4, 0.4, 0),
  //      S x T = (0, 0, -0.4*0.4 - 0.4*0.4) = (0, 0, -0.32)
  //   b: S = a' - c' = (0, -0.4, 0), T = c' + a' - 2b' = (-0.8, 0.4, 0), z = 0 - 0.32 = -0.32
  //   c: S = b' - a' = (0.4, 0, 0), T = a' + b' - 2c' = (0.4, -0.8, 0), z = -0.32 - 0 = -0.32
  // So pbrt's normals point to -z, the side from which (a, b, c) runs clockwise.
  ASSERT_EQ(mesh.normals.size(), 3u);
  for (const glm::vec3& n : mesh.normals) expect_near(n, {0, 0, -0.32f}, "normal");
  expect_winding_follows_normals(mesh);
}

TEST(LoopSubdiv, SingleTriangleLevel1) {
  // Refine. Even (boundary): 3/4 self + 1/8 each neighbour:
  //   a1 = (1/8, 1/8), b1 = (3/4 + 0, 1/8) = (0.75, 0.125), c1 = (0.125, 0.75).
  // Odd (boundary edges): midpoints, made in the order edge 0 (ab), 1 (bc), 2 (ca):
  //   m_ab = (0.5, 0), m_bc = (0.5, 0.5), m_ca = (0, 0.5).
  // Limit. a1 (valence 2, neighbours m_ab, m_ca): 3/5 (1/8, 1/8) + 1/5 (0.5, 0.5) = (0.175, 0.175)
  //   b1 (m_ab, m_bc): 3/5 (0.75, 0.125) + 1/5 (1.0, 0.5) = (0.65, 0.175); c1 likewise
  //   (0.175, 0.65).
  //   m_ab (valence 4, boundary neighbours a1, b1): 3/5 (0.5, 0) + 1/5 (0.875, 0.25)
  //   = (0.475, 0.05); m_bc (b1, c1): (0.3, 0.3) + 1/5 (0.875, 0.875) = (0.475, 0.475);
  //   m_ca (c1, a1): (0, 0.3) + 1/5 (0.25, 0.875) = (0.05, 0.475).
  const IndexedMesh mesh = loop_subdivide(kTriangle, {0, 1, 2}, 1, "t");
  expect_positions(mesh, {{0.175f, 0.175f, 0},
                          {0.65f, 0.175f, 0},
                          {0.175f, 0.65f, 0},
                          {0.475f, 0.05f, 0},
                          {0.475f, 0.475f, 0},
                          {0.05f, 0.475f, 0}});
  // pbrt's children: corner a (a, m_ab, m_ca) = (0, 3, 5), corner b (m_ab, b, m_bc) = (3, 1, 4),
  // corner c (m_ca, m_bc, c) = (5, 4, 2), middle (3, 4, 5); each as (v0, v2, v1).
  EXPECT_EQ(mesh.indices, (Indices{0, 5, 3, 3, 4, 1, 5, 2, 4, 3, 5, 4}));
  for (const glm::vec3& n : mesh.normals) {
    EXPECT_NEAR(n.x, 0.0f, kTolerance);
    EXPECT_NEAR(n.y, 0.0f, kTolerance);
    EXPECT_LT(n.z, 0.0f);
  }
  expect_winding_follows_normals(mesh);
}

// A regular tetrahedron centred on the origin (sum of the corners 0), counter-clockwise seen
// from outside: every vertex interior with valence 3, beta = 3/16.
const Points kTetrahedron = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
const Indices kTetrahedronFaces = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};

TEST(LoopSubdiv, TetrahedronLevel0) {
  // gamma(3) = 1/(3 + 3/(8 * 3/16)) = 1/(3 + 2) = 1/5; limit = (1 - 3/5) p + 1/5 (sum of the other
  // three) = 2/5 p + 1/5 (-p) = p/5.
  const IndexedMesh mesh = loop_subdivide(kTetrahedron, kTetrahedronFaces, 0, "t");
  expect_positions(
      mesh, {{0.2f, 0.2f, 0.2f}, {0.2f, -0.2f, -0.2f}, {-0.2f, 0.2f, -0.2f}, {-0.2f, -0.2f, 0.2f}});
  // Normal at a: start face = the last face naming a = (a, d, b). The ring walks next vertex,
  // then the face across (a, next): d', c', b' = (-.2,-.2,.2), (-.2,.2,-.2), (.2,-.2,-.2).
  //   S = 1 d' - 1/2 c' - 1/2 b' = (-.2, -.2, .2) + (0, 0, .2) = (-.2, -.2, .4)
  //   T = 0 d' + (√3/2) c' - (√3/2) b' = (√3/2)(-.4, .4, 0)
  //   S x T = (-.4 * .2√3, .4 * -.2√3, -.2 * .2√3 - .2 * .2√3) = -0.08√3 (1, 1, 1): inward.
  const float k = 0.08f * std::sqrt(3.0f);
  expect_near(mesh.normals[0], {-k, -k, -k}, "normal at a");
  // The ring is clockwise seen from outside, so every normal points inward ...
  for (std::size_t i = 0; i < 4; ++i) EXPECT_LT(glm::dot(mesh.normals[i], mesh.positions[i]), 0);
  // ... and each triangle comes back turned over, counter-clockwise about them.
  expect_winding_follows_normals(mesh);
}

TEST(LoopSubdiv, TetrahedronWoundClockwiseHasOutwardNormals) {
  // The same tetrahedron wound the other way round (each face's corners 1 and 2 swapped).
  const Indices faces = {0, 2, 1, 0, 3, 2, 0, 1, 3, 1, 2, 3};
  for (int levels = 0; levels <= 2; ++levels) {
    const IndexedMesh mesh = loop_subdivide(kTetrahedron, faces, levels, "t");
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      EXPECT_GT(glm::dot(mesh.normals[i], mesh.positions[i]), 0) << "level " << levels;
    }
    expect_winding_follows_normals(mesh);
  }
}

TEST(LoopSubdiv, TetrahedronLevel1) {
  // Even: (1 - 3 * 3/16) p + 3/16 (-p) = 7/16 p - 3/16 p = p/4.
  // Odd on edge ab: 3/8 (a + b) + 1/8 (c + d) = 3/8 (a + b) - 1/8 (a + b) = (a + b)/4.
  // Made in the order: face 0 ab, bc, ca; face 1 (a c d) cd, da; face 2 (a d b) db.
  // Limit of an even vertex (valence 3, gamma 1/5): its ring is the three odd vertices around
  // it, sum ((a+b) + (a+c) + (a+d))/4 = (3a - a)/4 = a/2; 2/5 * a/4 + 1/5 * a/2 = a/5.
  // Limit of an odd vertex (valence 6, gamma = 1/(6 + 3/(8/16)) = 1/12): ring a/4, b/4 and the
  // odd vertices of ac, bc, ad, bd, sum (a + b)/4 + (2a + 2b + 2c + 2d)/4 = (a + b)/4;
  // 1/2 * (a + b)/4 + 1/12 * (a + b)/4 = 7 (a + b)/48.
  const IndexedMesh mesh = loop_subdivide(kTetrahedron, kTetrahedronFaces, 1, "t");
  const float e = 14.0f / 48.0f;  // 7/48 * 2
  expect_positions(mesh, {{0.2f, 0.2f, 0.2f},
                          {0.2f, -0.2f, -0.2f},
                          {-0.2f, 0.2f, -0.2f},
                          {-0.2f, -0.2f, 0.2f},
                          {e, 0, 0},     // ab
                          {0, 0, -e},    // bc
                          {0, e, 0},     // ca
                          {-e, 0, 0},    // cd
                          {0, 0, e},     // da
                          {0, -e, 0}});  // db
  for (std::size_t i = 0; i < 10; ++i) EXPECT_LT(glm::dot(mesh.normals[i], mesh.positions[i]), 0);
  expect_winding_follows_normals(mesh);
}

TEST(LoopSubdiv, TriangleCountsAreFourToTheLevels) {
  for (int levels = 0; levels <= 5; ++levels) {
    const IndexedMesh mesh = loop_subdivide(kTetrahedron, kTetrahedronFaces, levels, "t");
    EXPECT_EQ(mesh.triangle_count(), std::size_t{4} << (2 * levels));
    // A closed mesh: V - E + F = 2 with E = 3F/2.
    EXPECT_EQ(mesh.positions.size(), 2 + mesh.triangle_count() / 2);
  }
  EXPECT_EQ(loop_subdivide(kTriangle, {0, 1, 2}, 10, "t").triangle_count(), std::size_t{1} << 20);
}

// The octahedron ±x (0, 1), ±y (2, 3), ±z (4, 5), counter-clockwise from outside: valence 4.
const Points kOctahedron = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
const Indices kOctahedronFaces = {0, 2, 4, 1, 4, 2, 0, 4, 3, 1, 3, 4,
                                  0, 5, 2, 1, 2, 5, 0, 3, 5, 1, 5, 3};

TEST(LoopSubdiv, OctahedronLevels0And1) {
  // beta(4) = 3/32, gamma(4) = 1/(4 + 3/(8 * 3/32)) = 1/(4 + 4) = 1/8.
  // Level 0: +x's ring is ±y, ±z, sum 0: limit (1 - 4/8) x = x/2.
  const IndexedMesh level0 = loop_subdivide(kOctahedron, kOctahedronFaces, 0, "t");
  for (std::size_t i = 0; i < 6; ++i) expect_near(level0.positions[i], 0.5f * kOctahedron[i], "l0");
  // Level 1. Even: (1 - 4 * 3/32) x + 3/32 * 0 = 5/8 x. Odd on (x, y): 3/8 (x + y) + 1/8 (z - z).
  // Limit of even x: ring = the odd vertices 3/8 (x ± y), 3/8 (x ± z), sum 3/2 x;
  //   1/2 * 5/8 x + 1/8 * 3/2 x = 5/16 x + 3/16 x = x/2.
  // Limit of odd (x, y) (valence 6, 1/12): ring 5/8 x, 5/8 y, and 3/8 (x + z), 3/8 (y + z),
  //   3/8 (x - z), 3/8 (y - z); sum 5/8 (x + y) + 3/4 (x + y) = 11/8 (x + y);
  //   1/2 * 3/8 (x + y) + 1/12 * 11/8 (x + y) = (18 + 11)/96 (x + y) = 29/96 (x + y).
  const IndexedMesh level1 = loop_subdivide(kOctahedron, kOctahedronFaces, 1, "t");
  ASSERT_EQ(level1.positions.size(), 18u);
  for (std::size_t i = 0; i < 6; ++i) expect_near(level1.positions[i], 0.5f * kOctahedron[i], "l1");
  // The first face (x, y, z) makes the odd vertices of xy, yz, zx, in that order.
  const float m = 29.0f / 96.0f;
  expect_near(level1.positions[6], {m, m, 0}, "xy");
  expect_near(level1.positions[7], {0, m, m}, "yz");
  expect_near(level1.positions[8], {m, 0, m}, "zx");
  for (std::size_t i = 6; i < 18; ++i) {
    const glm::vec3 p = glm::abs(level1.positions[i]);
    EXPECT_NEAR(p.x + p.y + p.z, 2 * m, kTolerance) << i;
    EXPECT_NEAR(std::fmax(p.x, std::fmax(p.y, p.z)), m, kTolerance) << i;
  }
  for (std::size_t i = 0; i < 18; ++i) {
    EXPECT_LT(glm::dot(level1.normals[i], level1.positions[i]), 0);
  }
  expect_winding_follows_normals(level1);
  EXPECT_EQ(level1.triangle_count(), 32u);
}

// A square pyramid without its base: apex o = (0,0,1) interior with valence 4, and the four base
// corners p0..p3 = (1,0,0), (0,1,0), (-1,0,0), (0,-1,0) on the boundary with valence 3.
const Points kPyramid = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
const Indices kPyramidFaces = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1};

TEST(LoopSubdiv, InteriorAndBoundaryVerticesLevel0) {
  // o: 1/2 o + 1/8 (p0 + p1 + p2 + p3) = (0, 0, 0.5).
  // p0: boundary neighbours p1 and p3 (o is between them in the ring): 3/5 p0 + 1/5 (p1 + p3)
  //   = (0.6, 0, 0); the others likewise 0.6 p_k.
  const IndexedMesh mesh = loop_subdivide(kPyramid, kPyramidFaces, 0, "t");
  expect_positions(mesh, {{0, 0, 0.5f}, {0.6f, 0, 0}, {0, 0.6f, 0}, {-0.6f, 0, 0}, {0, -0.6f, 0}});
  EXPECT_LT(mesh.normals[0].z, 0.0f);  // against the +z the faces are counter-clockwise about
  expect_winding_follows_normals(mesh);
}

TEST(LoopSubdiv, InteriorAndBoundaryVerticesLevel1) {
  // Refine. Even o (beta 3/32): (1 - 12/32) o + 3/32 * 0 = (0, 0, 0.625).
  //   Even p0 (boundary): 3/4 p0 + 1/8 (p1 + p3) = (0.75, 0, 0).
  //   Odd (o, p0), interior: 3/8 (o + p0) + 1/8 (p1 + p3) = (0.375, 0, 0.375).
  //   Odd (p0, p1), boundary: (0.5, 0.5, 0).
  // Limit. o (valence 4): 1/2 (0, 0, 0.625) + 1/8 (4 * 0.375 in z) = (0, 0, 0.3125 + 0.1875).
  //   p0 (boundary, neighbours (0.5, ±0.5, 0)): 3/5 (0.75, 0, 0) + 1/5 (1, 0, 0) = (0.65, 0, 0).
  //   (o, p0) (valence 6): ring o1 (0,0,.625), p0_1 (.75,0,0), (.5,.5,0), (0,.375,.375),
  //   (.5,-.5,0), (0,-.375,.375): sum (1.75, 0, 1.375);
  //   1/2 (.375, 0, .375) + 1/12 (1.75, 0, 1.375) = (18/96 + 14/96, 0, 18/96 + 11/96)
  //   = (1/3, 0, 29/96).
  //   (p0, p1) (boundary, neighbours p0_1 and p1_1): 3/5 (.5, .5, 0) + 1/5 (.75, .75, 0)
  //   = (0.45, 0.45, 0).
  // Odd order: face 0 (o p0 p1): o-p0, p0-p1, p1-o; face 1 (o p1 p2): p1-p2, p2-o; face 2:
  // p2-p3, p3-o; face 3 (o p3 p0): p3-p0 (p0-o is face 0's).
  const IndexedMesh mesh = loop_subdivide(kPyramid, kPyramidFaces, 1, "t");
  const float third = 1.0f / 3.0f, h = 29.0f / 96.0f;
  expect_positions(mesh, {{0, 0, 0.5f},
                          {0.65f, 0, 0},
                          {0, 0.65f, 0},
                          {-0.65f, 0, 0},
                          {0, -0.65f, 0},
                          {third, 0, h},
                          {0.45f, 0.45f, 0},
                          {0, third, h},
                          {-0.45f, 0.45f, 0},
                          {-third, 0, h},
                          {-0.45f, -0.45f, 0},
                          {0, -third, h},
                          {0.45f, -0.45f, 0}});
  expect_winding_follows_normals(mesh);
  EXPECT_EQ(mesh.triangle_count(), 16u);
}

TEST(LoopSubdiv, RefusesAnEdgeOfThreeTriangles) {
  const Points points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  EXPECT_EQ(error_of(points, {0, 1, 2, 1, 0, 3, 1, 0, 4}, 1),
            "scene.pbrt:7: loopsubdiv: non-manifold edge between vertices 0 and 1 (used by "
            "triangles 0, 1 and 2)");
}

TEST(LoopSubdiv, RefusesInconsistentOrientation) {
  const Points points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  EXPECT_EQ(error_of(points, {0, 1, 2, 0, 1, 3}, 0),
            "scene.pbrt:7: loopsubdiv: non-manifold edge between vertices 0 and 1 (triangles 0 "
            "and 1 both run from 0 to 1: inconsistent orientation)");
}

TEST(LoopSubdiv, RefusesBadInput) {
  EXPECT_EQ(error_of(kTriangle, {0, 1, 3}, 1),
            "scene.pbrt:7: loopsubdiv: index 3 of triangle 0 is out of range (3 points)");
  EXPECT_EQ(error_of(kTriangle, {0, 1, 2}, -1), "scene.pbrt:7: loopsubdiv: negative \"levels\" -1");
  EXPECT_EQ(error_of(kTriangle, {0, 1, 2}, 11),
            "scene.pbrt:7: loopsubdiv: \"levels\" 11 is over the limit of 10");
  EXPECT_EQ(error_of(kTriangle, {}, 1),
            "scene.pbrt:7: loopsubdiv: no triangles (\"indices\" is empty)");
  EXPECT_EQ(error_of(kTriangle, {0, 1, 2, 0}, 1),
            "scene.pbrt:7: loopsubdiv: 4 indices, not a multiple of 3");
  EXPECT_EQ(error_of(kTriangle, {0, 1, 1}, 1),
            "scene.pbrt:7: loopsubdiv: triangle 0 repeats a vertex (0 1 1)");
  EXPECT_EQ(error_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}}, {0, 1, 2}, 1),
            "scene.pbrt:7: loopsubdiv: point 3 is used by no triangle");
  Indices many;
  for (int t = 0; t < 1025; ++t) many.insert(many.end(), {0, 1, 2});
  EXPECT_EQ(error_of(kTriangle, many, 10),
            "scene.pbrt:7: loopsubdiv: 1025 triangles at 10 levels would make more than 2^30 "
            "triangles");
}

}  // namespace
}  // namespace hrpp
