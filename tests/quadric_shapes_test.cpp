// host/scene/quadric_shapes: the sphere, disk and cylinder meshes stay within 1e-3 of the radius
// of the true surface (the vertices, and every point of every triangle, so every edge midpoint
// and centroid), their area is within 0.2% of pbrt's closed form, they wind counter-clockwise
// about pbrt's outward (+z for the disk) normal, keep pbrt's (u, v), clip to zmin, zmax, phimax
// and innerradius, and have no degenerate triangles; a full sphere is closed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "scene/quadric_shapes.h"

namespace hrpp {
namespace {

using glm::dvec3;

constexpr double kPi = 3.14159265358979323846;
constexpr double kSag = 1e-3;
constexpr int kSegments = 100;  // quadric_segments(1e-3), checked below

struct Corners {
  dvec3 a, b, c;
  dvec3 normal() const { return glm::cross(b - a, c - a); }
  dvec3 centroid() const { return (a + b + c) / 3.0; }
};

Corners corners(const IndexedMesh& mesh, std::size_t t) {
  return {dvec3(mesh.positions[mesh.indices[3 * t]]),
          dvec3(mesh.positions[mesh.indices[3 * t + 1]]),
          dvec3(mesh.positions[mesh.indices[3 * t + 2]])};
}

double area(const IndexedMesh& mesh) {
  double sum = 0.0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    sum += 0.5 * glm::length(corners(mesh, t).normal());
  }
  return sum;
}

double segment_distance(const dvec3& p, const dvec3& a, const dvec3& b) {
  const dvec3 ab = b - a;
  const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
  return glm::length(p - (a + t * ab));
}

// Distance from p to the triangle: to its plane if p projects inside, else to the nearest edge.
double triangle_distance(const dvec3& p, const Corners& k) {
  const dvec3 n = k.normal();
  const dvec3 q = p - glm::dot(p - k.a, n) / glm::dot(n, n) * n;
  const bool inside = glm::dot(glm::cross(k.b - k.a, q - k.a), n) >= 0 &&
                      glm::dot(glm::cross(k.c - k.b, q - k.b), n) >= 0 &&
                      glm::dot(glm::cross(k.a - k.c, q - k.c), n) >= 0;
  if (inside) return glm::length(p - q);
  return std::min({segment_distance(p, k.a, k.b), segment_distance(p, k.b, k.c),
                   segment_distance(p, k.c, k.a)});
}

dvec3 flat(const dvec3& p) { return {p.x, p.y, 0.0}; }

// The least distance from the z axis of a point of the triangle (the axis misses it).
double axis_distance(const Corners& k) {
  const dvec3 a = flat(k.a), b = flat(k.b), c = flat(k.c), o(0.0);
  return std::min(
      {segment_distance(o, a, b), segment_distance(o, b, c), segment_distance(o, c, a)});
}

double phi_of(const glm::vec3& p) {
  const double phi = std::atan2(double{p.y}, double{p.x});
  return phi < 0 ? phi + 2 * kPi : phi;
}

void expect_no_degenerate_triangles(const IndexedMesh& mesh, double radius) {
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    EXPECT_GT(glm::length(corners(mesh, t).normal()), 1e-9 * radius * radius) << "triangle " << t;
  }
}

// Each triangle is counter-clockwise about its corners' normals and about `outward(centroid)`.
template <typename Outward>
void expect_winding(const IndexedMesh& mesh, Outward outward) {
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const Corners k = corners(mesh, t);
    EXPECT_GT(glm::dot(k.normal(), outward(k.centroid())), 0.0) << "triangle " << t;
    for (int j = 0; j < 3; ++j) {
      EXPECT_GT(glm::dot(k.normal(), dvec3(mesh.normals[mesh.indices[3 * t + j]])), 0.0);
    }
  }
}

// The largest depth of a triangle point inside a sphere of radius r about the origin.
double sphere_sag(const IndexedMesh& mesh, double r) {
  double sag = 0.0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    sag = std::max(sag, r - triangle_distance(dvec3(0.0), corners(mesh, t)));
  }
  return sag;
}

TEST(QuadricShapes, SegmentsRule) {
  // 1 - cos(π√2/n) <= 1e-3  <=>  n >= π√2 / acos(0.999) = 4.442883 / 0.0447250 = 99.34.
  EXPECT_EQ(quadric_segments(1e-3f), 100);
  EXPECT_EQ(quadric_segments(), 100);
  // 1e-2: 4.442883 / acos(0.99) = 4.442883 / 0.1415394 = 31.39.
  EXPECT_EQ(quadric_segments(1e-2f), 32);
  EXPECT_EQ(quadric_segments(0.9f), 4);  // 4.442883 / acos(0.1) = 4.442883 / 1.470629 = 3.02
  EXPECT_EQ(quadric_segments(1.5f), 3);  // 2.12, raised to the least of 3
  EXPECT_EQ(quadric_segments(0.0f), 4096);
}

TEST(QuadricShapes, FullSphere) {
  const double r = 2.0;
  const IndexedMesh mesh = tessellate_sphere(2.0f, -2.0f, 2.0f, 360.0f, kSegments);
  // 100 columns; 50 rows of theta: two fans of 100 and 48 bands of 200 triangles.
  EXPECT_EQ(mesh.triangle_count(), 200u + 48u * 200u);
  for (const glm::vec3& p : mesh.positions) EXPECT_NEAR(glm::length(dvec3(p)), r, 1e-6 * r);
  EXPECT_LT(sphere_sag(mesh, r) / r, kSag);
  EXPECT_NEAR(area(mesh) / (4 * kPi * r * r), 1.0, 2e-3);
  expect_winding(mesh, [](const dvec3& c) { return c; });
  expect_no_degenerate_triangles(mesh, r);
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3 n = mesh.normals[i], p = mesh.positions[i];
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(n, p / 2.0f), 1.0f, 1e-5f);
    // pbrt: v = (theta - theta(zmin)) / (theta(zmax) - theta(zmin)) = (theta - π) / -π.
    const double theta = std::acos(std::clamp(double{p.z} / r, -1.0, 1.0));
    EXPECT_NEAR(mesh.uvs[i].y, (theta - kPi) / -kPi, 1e-5);
  }
}

TEST(QuadricShapes, FullSphereIsClosed) {
  // Welded by exact position, every edge is run once each way: the seam's columns and the
  // pole's apexes coincide bit for bit.
  const IndexedMesh mesh = tessellate_sphere(1.0f, -1.0f, 1.0f, 360.0f, 17);
  using Key = std::tuple<float, float, float, float, float, float>;
  std::map<Key, int> runs;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    for (int j = 0; j < 3; ++j) {
      const glm::vec3 a = mesh.positions[mesh.indices[3 * t + j]];
      const glm::vec3 b = mesh.positions[mesh.indices[3 * t + (j + 1) % 3]];
      ++runs[{a.x, a.y, a.z, b.x, b.y, b.z}];
    }
  }
  for (const auto& [edge, count] : runs) {
    EXPECT_EQ(count, 1);
    const auto [ax, ay, az, bx, by, bz] = edge;
    EXPECT_EQ(runs.count({bx, by, bz, ax, ay, az}), 1u);
  }
}

TEST(QuadricShapes, PartialSphere) {
  const double r = 1.5, zmin = -0.5, zmax = 1.2, phimax = 270.0 * kPi / 180.0;
  const IndexedMesh mesh = tessellate_sphere(1.5f, -0.5f, 1.2f, 270.0f, kSegments);
  const double theta_min = std::acos(zmin / r), theta_max = std::acos(zmax / r);
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3 p = mesh.positions[i];
    EXPECT_GE(p.z, zmin - 1e-6);
    EXPECT_LE(p.z, zmax + 1e-6);
    const double phi = mesh.uvs[i].x == 0.0f ? 0.0 : phi_of(p);
    EXPECT_NEAR(mesh.uvs[i].x, phi / phimax, 1e-5);
    const double theta = std::acos(double{p.z} / r);
    EXPECT_NEAR(mesh.uvs[i].y, (theta - theta_min) / (theta_max - theta_min), 1e-5);
  }
  EXPECT_LT(sphere_sag(mesh, r) / r, kSag);
  EXPECT_NEAR(area(mesh) / (phimax * r * (zmax - zmin)), 1.0, 2e-3);  // pbrt's Sphere::Area
  expect_winding(mesh, [](const dvec3& c) { return c; });
  expect_no_degenerate_triangles(mesh, r);
}

TEST(QuadricShapes, SphereClampsAndOrdersZ) {
  // zmin above the radius clamps to r (a north pole), and zmin > zmax swaps: z in [-0.3, 1].
  const IndexedMesh mesh = tessellate_sphere(1.0f, 2.0f, -0.3f, 360.0f, kSegments);
  float lowest = 1.0f, highest = -1.0f;
  for (const glm::vec3& p : mesh.positions) {
    lowest = std::min(lowest, p.z);
    highest = std::max(highest, p.z);
  }
  EXPECT_FLOAT_EQ(lowest, -0.3f);
  EXPECT_FLOAT_EQ(highest, 1.0f);
  EXPECT_NEAR(area(mesh) / (2 * kPi * 1.3), 1.0, 2e-3);
  EXPECT_LT(sphere_sag(mesh, 1.0), kSag);
  expect_winding(mesh, [](const dvec3& c) { return c; });
  expect_no_degenerate_triangles(mesh, 1.0);
}

TEST(QuadricShapes, Cylinder) {
  const double r = 0.7, phimax = 90.0 * kPi / 180.0;
  const IndexedMesh mesh = tessellate_cylinder(0.7f, 1.0f, -2.0f, 90.0f, kSegments);  // swapped
  EXPECT_EQ(mesh.triangle_count(), 2u * 25u);
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3 p = mesh.positions[i];
    EXPECT_NEAR(glm::length(flat(dvec3(p))), r, 1e-6);
    EXPECT_TRUE(p.z == -2.0f || p.z == 1.0f);
    EXPECT_NEAR(mesh.uvs[i].y, (p.z + 2.0) / 3.0, 1e-6);  // pbrt: (z - zmin) / (zmax - zmin)
    EXPECT_NEAR(mesh.uvs[i].x, phi_of(p) / phimax, 1e-5);
    EXPECT_NEAR(glm::dot(dvec3(mesh.normals[i]), flat(dvec3(p)) / r), 1.0, 1e-6);
    EXPECT_EQ(mesh.normals[i].z, 0.0f);
  }
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    EXPECT_GT(axis_distance(corners(mesh, t)) / r, 1.0 - kSag);
  }
  EXPECT_NEAR(area(mesh) / (3.0 * r * phimax), 1.0, 2e-3);  // pbrt's Cylinder::Area
  expect_winding(mesh, [](const dvec3& c) { return flat(c); });
  expect_no_degenerate_triangles(mesh, r);
}

TEST(QuadricShapes, DiskWithHole) {
  const double outer = 2.0, inner = 0.6, phimax = 200.0 * kPi / 180.0;
  const IndexedMesh mesh = tessellate_disk(0.5f, 2.0f, 0.6f, 200.0f, kSegments);
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3 p = mesh.positions[i];
    const double rho = glm::length(flat(dvec3(p)));
    EXPECT_EQ(p.z, 0.5f);
    EXPECT_TRUE(std::abs(rho - outer) < 1e-6 || std::abs(rho - inner) < 1e-6) << rho;
    EXPECT_NEAR(mesh.uvs[i].y, (outer - rho) / (outer - inner), 1e-6);  // 0 on the rim
    EXPECT_NEAR(mesh.uvs[i].x, phi_of(p) / phimax, 1e-5);
    EXPECT_EQ(mesh.normals[i], glm::vec3(0, 0, 1));
  }
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const Corners k = corners(mesh, t);
    // Points of the mesh in the hole lie under an inner chord.
    EXPECT_GT(axis_distance(k), inner - kSag * outer);
    // The rim between two rim corners is covered up to an outer chord's sag.
    const dvec3 ends[3][2] = {{k.a, k.b}, {k.b, k.c}, {k.c, k.a}};
    for (const auto& e : ends) {
      const bool rim = glm::length(flat(e[0])) > 1.5 && glm::length(flat(e[1])) > 1.5;
      if (rim) {
        EXPECT_GT(glm::length(flat(0.5 * (e[0] + e[1]))), outer * (1.0 - kSag));
      }
    }
  }
  EXPECT_NEAR(area(mesh) / (phimax / 2 * (outer * outer - inner * inner)), 1.0, 2e-3);
  expect_winding(mesh, [](const dvec3&) { return dvec3(0, 0, 1); });
  expect_no_degenerate_triangles(mesh, outer);
}

TEST(QuadricShapes, FullDiskIsAFan) {
  const IndexedMesh mesh = tessellate_disk(0.0f, 1.0f, 0.0f, 360.0f, kSegments);
  EXPECT_EQ(mesh.triangle_count(), 100u);
  EXPECT_NEAR(area(mesh) / kPi, 1.0, 2e-3);
  expect_winding(mesh, [](const dvec3&) { return dvec3(0, 0, 1); });
  expect_no_degenerate_triangles(mesh, 1.0);
  // The centre is one apex per segment, at v = 1 and the segment's middle u.
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (mesh.positions[i] == glm::vec3(0.0f)) {
      EXPECT_EQ(mesh.uvs[i].y, 1.0f);
    }
  }
}

TEST(QuadricShapes, NoAreaMakesNoTriangles) {
  EXPECT_EQ(tessellate_sphere(0.0f, -1.0f, 1.0f, 360.0f, kSegments).triangle_count(), 0u);
  EXPECT_EQ(tessellate_sphere(1.0f, 0.5f, 0.5f, 360.0f, kSegments).triangle_count(), 0u);
  EXPECT_EQ(tessellate_sphere(1.0f, -1.0f, 1.0f, 0.0f, kSegments).triangle_count(), 0u);
  EXPECT_EQ(tessellate_sphere(-1.0f, -1.0f, 1.0f, 360.0f, kSegments).triangle_count(), 0u);
  EXPECT_EQ(tessellate_cylinder(1.0f, 1.0f, 1.0f, 360.0f, kSegments).triangle_count(), 0u);
  EXPECT_EQ(tessellate_disk(0.0f, 1.0f, 1.0f, 360.0f, kSegments).triangle_count(), 0u);
  EXPECT_EQ(tessellate_disk(0.0f, 1.0f, 0.0f, -5.0f, kSegments).triangle_count(), 0u);
  EXPECT_EQ(tessellate_disk(0.0f, std::nanf(""), 0.0f, 360.0f, kSegments).triangle_count(), 0u);
}

TEST(QuadricShapes, PhimaxAboveAFullTurnIsAFullTurn) {
  EXPECT_EQ(tessellate_cylinder(1.0f, 0.0f, 1.0f, 720.0f, kSegments).triangle_count(),
            tessellate_cylinder(1.0f, 0.0f, 1.0f, 360.0f, kSegments).triangle_count());
}

}  // namespace
}  // namespace hrpp
