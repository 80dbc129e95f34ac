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
#include <span>
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
  bool huge = false;  // with the huge triangle
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

// The same closest hit, bit for bit: triangle, t, u and v.
inline bool same_hit(const gpu::Hit& a, const gpu::Hit& b) {
  return a.prim == b.prim && a.t == b.t && a.u == b.u && a.v == b.v;
}

// GoogleTest's parameter name for a frame (extreme or leak): its name, '-' written 'm'.
template <class ParamInfo>
std::string frame_param_name(const ParamInfo& info) {
  std::string n = info.param.name;
  for (char& c : n)
    if (c == '-') c = 'm';
  return n;
}

// Every ray of the groups, in group order.
std::vector<gpu::Ray> group_rays(const std::vector<RayGroup>& groups);

// The rays a device runs over an extreme scene: group_rays(x.groups), then invalid_rays(centre).
std::vector<gpu::Ray> extreme_rays(const ExtremeScene& x, const glm::vec3& centre);

// Of a device's closest hits over extreme_rays(x, ...), how many break the exact rules (not
// checked with the huge triangle: see extreme_cases.cpp) or are an invalid ray's hit.
int count_extreme_failures(const ExtremeScene& x, std::span<const gpu::Hit> hits);

// Of the closest hits `hits` (hits[i] for ray i of group_rays(groups); more may follow), how many
// break their group's rule: kHitRange, a hit outside [first, last) or a miss (an escape);
// kAvoidRange, a hit inside it.
int count_rule_breaks(const std::vector<RayGroup>& groups, std::span<const gpu::Hit> hits);

// Leak suite: two closed meshes of thousands of triangles, a subdivided icosphere (radius R,
// 5120 triangles) and the surface of a cube of side 2R cut into 16 × 16 quads a face (3072
// triangles), centred at `offset` and at offset + (3R, 0, 0). Rays, every one of which must
// hit its own mesh (Rule::kHitRange; a miss or a hit elsewhere is an escape):
//   <mesh>_centre       from the centre to every vertex and every edge midpoint;
//   <mesh>_off_centre   the same from an interior point off the centre;
//   <mesh>_near_surface from points slightly inside the surface (under every vertex and edge
//                       midpoint, deeper than the mesh's chord sag plus 8 float spacings so the
//                       float point is inside) to that vertex, to its neighbours (rays nearly
//                       along the surface) and to that midpoint.
// and one group whose origins lie on the surface, where either answer is right (Rule::
// kOracleOnly; what it checks is that no box hides a hit of the triangle test, see
// tests/extreme_rays_test.cpp):
//   box_on_face         from every edge midpoint of the cube (a point "just inside" by less than
//                       the float spacing rounds onto the face plane like this) to the
//                       neighbours of the edge's first end: rays in the face's plane (one zero
//                       direction component, origin in the plane of the boxes of that face) and
//                       rays into the cube.
struct LeakFrame {
  std::string name;
  double radius = 1.0;
  glm::dvec3 offset{0.0};
};

inline void PrintTo(const LeakFrame& f, std::ostream* os) { *os << f.name; }

// Translated by 0, 1e2, 1e4 (R = 1: 70 float spacings or more along every edge) and 1e6
// (R = 100, ~110 spacings an edge; R = 1 would leave ~1).
std::vector<LeakFrame> leak_frames();

struct LeakScene {
  LeakFrame frame;
  Scene scene;
  std::vector<RayGroup> groups;
};

LeakScene make_leak_scene(const LeakFrame& frame);

}  // namespace hrpp::test
