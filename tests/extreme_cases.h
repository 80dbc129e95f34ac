// The extreme-case suite's scenes and rays (tests/extreme_rays_test.cpp on the CPU reference,
// tests/extreme_rays_gpu_test.cpp on the device). One scene, built in unit coordinates and placed
// by a Frame (scale, then translation, in double, rounded once to float):
//   - a closed icosphere (radius 1, 320 triangles) and a closed cube (12), for leak tests;
//   - a floor of 8 × 8 quads (128 coplanar triangles sharing edges and vertices);
//   - degenerate triangles (a point, a repeated vertex, collinear vertices) above the floor;
//   - tiny triangles (edges 1e-7 of the unit) and, in a second variant, one huge triangle
//     (1e14 across) behind everything.
// Ray groups (rays go through the float positions of vertices and edges themselves):
//   inside_sphere, inside_cube  from inside closed meshes at vertices, edge midpoints, corners
//                               and random directions: every one must hit its mesh (no escape);
//   floor_down                  straight down through grid vertices, edges and cells: must hit;
//   axis                        one or two zero direction components, in and beside planes;
//   box_faces                   origins on the faces of the sphere's bounding box;
//   on_surface                  origins on sphere vertices and edges, inward and outward;
//   grazing                     onto the floor at 1e-1 .. 1e-6 rad;
//   tiny                        at the tiny triangles;
//   leaving_floor, leaving_sphere  secondary rays off a surface at grazing angles, origins
//                               offset by host/trace/offset_ray.h: must not hit that surface.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gpu_types.h"
#include "scene/scene.h"

namespace hrpp::test {

struct Frame {
  std::string name;
  double scale = 1.0;
  glm::dvec3 offset{0.0};
};

inline void PrintTo(const Frame& f, std::ostream* os) { *os << f.name; }  // for GoogleTest

// unit; translated by 1e4; translated by 1e6 (scale 100, so the unit sphere stays many float
// steps wide); scaled by 1e-4; scaled by 1e4.
std::vector<Frame> extreme_frames();

struct RayGroup {
  std::string name;
  std::vector<gpu::Ray> rays;
  // Beyond the oracle: kHitRange: every ray's closest hit is a triangle in [first, last) (leak
  // tests, no fall-through); kAvoidRange: no ray hits a triangle in [first, last) at all
  // (self-intersection of secondary rays).
  enum class Rule { kOracleOnly, kHitRange, kAvoidRange } rule = Rule::kOracleOnly;
  int first = 0, last = 0;
};

struct ExtremeScene {
  Frame frame;
  Scene scene;
  int sphere_first = 0, sphere_last = 0;  // triangle id ranges [first, last)
  int cube_first = 0, cube_last = 0;
  int floor_first = 0, floor_last = 0;
  std::vector<RayGroup> groups;
};

// huge: add the huge triangle (the exact rules are then not checked: see extreme_cases.cpp).
ExtremeScene make_extreme_scene(const Frame& frame, bool huge);

// Rays with NaN / Inf / zero parts: each must miss (closest) and be free (any hit).
std::vector<gpu::Ray> invalid_rays(const glm::vec3& inside);

}  // namespace hrpp::test
