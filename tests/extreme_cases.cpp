#include "extreme_cases.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <tuple>
#include <utility>

#include "trace/offset_ray.h"

namespace hrpp::test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Unit-coordinate geometry, placed by the frame once.
struct Builder {
  const Frame& frame;
  Scene& scene;

  glm::vec3 place(const glm::dvec3& p) const { return glm::vec3(p * frame.scale + frame.offset); }
  int add(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    scene.triangles.push_back({place(a), place(b), place(c)});
    scene.shading.emplace_back();
    return static_cast<int>(scene.triangles.size() - 1);
  }
};

// Icosphere: an icosahedron subdivided `levels` times, vertices pushed to the unit sphere.
void icosphere(int levels, std::vector<glm::dvec3>& verts, std::vector<glm::ivec3>& faces) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  verts = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
           {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& v : verts) v = glm::normalize(v);
  faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
           {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
           {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      verts.push_back(glm::normalize(verts[a] + verts[b]));
      return mid[key] = static_cast<int>(verts.size() - 1);
    };
    std::vector<glm::ivec3> next;
    for (const auto& f : faces) {
      const int a = midpoint(f.x, f.y);
      const int b = midpoint(f.y, f.z);
      const int c = midpoint(f.z, f.x);
      next.push_back({f.x, a, c});
      next.push_back({f.y, b, a});
      next.push_back({f.z, c, b});
      next.push_back({a, b, c});
    }
    faces = std::move(next);
  }
}

// Surface of the cube [-1, 1]^3 cut into n × n quads a face, diagonals alternating.
void box_grid(int n, std::vector<glm::dvec3>& verts, std::vector<glm::ivec3>& faces) {
  std::map<std::tuple<int, int, int>, int> index;  // by integer grid position 0..n
  auto vertex = [&](const glm::ivec3& g) {
    const auto [it, fresh] = index.try_emplace({g.x, g.y, g.z}, static_cast<int>(verts.size()));
    if (fresh) verts.push_back(glm::dvec3(g) * (2.0 / n) - 1.0);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (const int side : {0, n})
      for (int i = 0; i < n; ++i)
        for (int k = 0; k < n; ++k) {
          auto at = [&](int di, int dk) {
            glm::ivec3 g;
            g[axis] = side;
            g[(axis + 1) % 3] = i + di;
            g[(axis + 2) % 3] = k + dk;
            return vertex(g);
          };
          const int a = at(0, 0), b = at(1, 0), c = at(1, 1), d = at(0, 1);
          if ((i + k) % 2) {
            faces.push_back({a, b, c});
            faces.push_back({a, c, d});
          } else {
            faces.push_back({a, b, d});
            faces.push_back({b, c, d});
          }
        }
}

gpu::Ray ray_between(const glm::vec3& from, const glm::vec3& to, float tmin = 0.0f) {
  return {from, tmin, to - from, kInf};
}

void push_valid(std::vector<gpu::Ray>& rays, const gpu::Ray& r) {
  if (r.dir != glm::vec3(0.0f)) rays.push_back(r);  // e.g. the midpoint of opposite corners
}

}  // namespace

std::vector<Frame> extreme_frames() {
  return {{"unit", 1.0, {0, 0, 0}},
          {"translated_1e4", 1.0, {1e4, -1e4, 1e4}},
          {"translated_1e6", 100.0, {1e6, 1e6, -1e6}},
          {"scaled_1e-4", 1e-4, {0, 0, 0}},
          {"scaled_1e4", 1e4, {0, 0, 0}}};
}

ExtremeScene make_extreme_scene(const Frame& frame, bool huge) {
  ExtremeScene x;
  x.frame = frame;
  x.huge = huge;
  x.scene.name = "extreme-" + frame.name;
  x.scene.materials.emplace_back();
  Builder b{frame, x.scene};

  // Closed icosphere, radius 1 at the origin.
  std::vector<glm::dvec3> sv;
  std::vector<glm::ivec3> sf;
  icosphere(2, sv, sf);
  x.sphere_first = static_cast<int>(x.scene.triangles.size());
  for (const auto& f : sf) b.add(sv[f.x], sv[f.y], sv[f.z]);
  x.sphere_last = static_cast<int>(x.scene.triangles.size());

  // Closed cube [2.5, 3.5] x [-0.5, 0.5] x [-0.5, 0.5].
  const glm::dvec3 cc(3, 0, 0);
  glm::dvec3 cv[8];
  for (int i = 0; i < 8; ++i)
    cv[i] = cc + glm::dvec3(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  x.cube_first = static_cast<int>(x.scene.triangles.size());
  for (const auto& q : quads) {
    b.add(cv[q[0]], cv[q[1]], cv[q[2]]);
    b.add(cv[q[0]], cv[q[2]], cv[q[3]]);
  }
  x.cube_last = static_cast<int>(x.scene.triangles.size());

  // Floor y = -2 over [-4, 4]^2: 8 x 8 quads, alternating diagonals.
  x.floor_first = static_cast<int>(x.scene.triangles.size());
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 p00(i - 4, -2, k - 4), p10(i - 3, -2, k - 4), p01(i - 4, -2, k - 3),
          p11(i - 3, -2, k - 3);
      if ((i + k) % 2) {
        b.add(p00, p01, p11);
        b.add(p00, p11, p10);
      } else {
        b.add(p00, p01, p10);
        b.add(p10, p01, p11);
      }
    }
  x.floor_last = static_cast<int>(x.scene.triangles.size());

  // Degenerate triangles above the floor, left of the sphere: never hit.
  b.add({-3, -1, 0}, {-3, -1, 0}, {-3, -1, 0});              // a point
  b.add({-3, -1, 1}, {-3, -1, 1}, {-2, -1, 1.5});            // repeated vertex
  b.add({-3.5, -1, -1}, {-3, -1, -1}, {-2.5, -1, -1});       // collinear
  b.add({-3.5, -1.5, -1}, {-3, -1, -0.5}, {-2.5, -0.5, 0});  // collinear, oblique

  // Tiny triangles (edges 1e-7) near (-3, 1, 0), and near the world origin in unit frames.
  const glm::dvec3 tp(-3, 1, 0);
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3 base = tp + glm::dvec3(0, 0, 0.25 * i);
    b.add(base, base + glm::dvec3(1e-7, 0, 0), base + glm::dvec3(0, 1e-7, 1e-8));
  }
  // Huge triangle behind everything (z = -20), 2e14 across: its own variant, since rays nearly
  // parallel to it get t errors beyond 100% in float (the oracle's bound allows them) and would
  // then count as leaks of the closed meshes.
  // 1e14 absolute at most, so the scaled frames keep it behind the other geometry; triangles
  // 1e17..4e18 across have their own test (extreme_rays_test.cpp, HugeTriangles).
  if (huge) {
    const double h = 1e14 / std::max(1.0, frame.scale);
    b.add({-h, -h, -20}, {h, -h, -20}, {0, h, -20});
  }

  const Scene& s = x.scene;
  auto P = [&](const glm::dvec3& p) { return b.place(p); };
  std::mt19937 rng(61);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto random_dir = [&] {
    glm::dvec3 d;
    do d = {u(rng), u(rng), u(rng)};
    while (glm::length(d) > 1.0 || glm::length(d) < 1e-3);
    return d;
  };

  // inside_sphere: from 3 interior points at every vertex, 200 edge midpoints, 100 random.
  {
    RayGroup g{"inside_sphere", {}, RayGroup::Rule::kHitRange, x.sphere_first, x.sphere_last};
    for (const glm::dvec3 o : {glm::dvec3(0), glm::dvec3(0.3, -0.2, 0.1), glm::dvec3(0, 0.9, 0)}) {
      for (std::size_t i = 0; i < s.triangles.size() && static_cast<int>(i) < x.sphere_last; ++i) {
        const Triangle& t = s.triangles[i];
        g.rays.push_back(ray_between(P(o), t.v0));                                  // at a vertex
        if (i % 2 == 0) g.rays.push_back(ray_between(P(o), 0.5f * (t.v0 + t.v1)));  // edge
      }
      for (int i = 0; i < 100; ++i) g.rays.push_back(ray_between(P(o), P(o + random_dir())));
    }
    x.groups.push_back(std::move(g));
  }
  // inside_cube: corners, edge midpoints, face centres (on the shared diagonals), random.
  {
    RayGroup g{"inside_cube", {}, RayGroup::Rule::kHitRange, x.cube_first, x.cube_last};
    for (const glm::dvec3 o : {cc, cc + glm::dvec3(0.1, 0.2, -0.3)}) {
      for (int i = 0; i < 8; ++i) {
        push_valid(g.rays, ray_between(P(o), P(cv[i])));
        for (int k = i + 1; k < 8; ++k)
          push_valid(g.rays, ray_between(P(o), P(0.5 * (cv[i] + cv[k]))));
      }
      for (int i = 0; i < 100; ++i) g.rays.push_back(ray_between(P(o), P(o + random_dir())));
    }
    // Axis-parallel rays from the centre (two zero components) and along face diagonals.
    for (int a = 0; a < 3; ++a)
      for (double sgn : {-1.0, 1.0}) {
        glm::dvec3 d(0);
        d[a] = sgn;
        g.rays.push_back(ray_between(P(cc), P(cc + d)));
      }
    x.groups.push_back(std::move(g));
  }
  // floor_down: straight down (0, -1, 0) through the floor's inner grid vertices, edges and
  // cells (its outer boundary is no shared edge: a hit there is either way).
  {
    RayGroup g{
        "floor_down", {}, RayGroup::Rule::kHitRange, 0, static_cast<int>(s.triangles.size())};
    for (int i = 1; i < 16; ++i)
      for (int k = 1; k < 16; ++k) {
        const glm::vec3 o = P({-4 + 0.5 * i, 3, -4 + 0.5 * k});
        const glm::vec3 on_floor = P({-4 + 0.5 * i, -2, -4 + 0.5 * k});
        g.rays.push_back({glm::vec3(on_floor.x, o.y, on_floor.z), 0.0f, {0, -1, 0}, kInf});
      }
    x.groups.push_back(std::move(g));
  }
  // axis: two zero components along x, y, z through the scene, in and just beside the floor
  // plane and the cube's faces; one zero component diagonals.
  {
    RayGroup g{"axis", {}, RayGroup::Rule::kOracleOnly, 0, 0};
    const glm::vec3 floor_pt = P({-6, -2, 0.5}), cube_face = P({0, 0.5, 0.25});
    const glm::vec3 step = P({0, 1e-3, 0}) - P({0, 0, 0});
    for (const glm::vec3 d : {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 0, 1),
                              glm::vec3(1, 0, 1), glm::vec3(1, 0, -1)}) {
      g.rays.push_back({floor_pt, 0.0f, d, kInf});         // in the floor plane: edge-on
      g.rays.push_back({floor_pt + step, 0.0f, d, kInf});  // just above
      g.rays.push_back({floor_pt - step, 0.0f, d, kInf});  // just below
      g.rays.push_back({cube_face, 0.0f, d, kInf});        // in the cube's top face plane
    }
    for (int a = 0; a < 3; ++a)
      for (float sgn : {-1.0f, 1.0f}) {
        glm::vec3 d(0.0f);
        d[a] = sgn;
        for (const glm::dvec3 o : {glm::dvec3(0, 0, 0), glm::dvec3(3, 0.5, 0.5),
                                   glm::dvec3(-5, -2, 0), glm::dvec3(0.5, 0.25, -5)})
          g.rays.push_back({P(o), 0.0f, d, kInf});
      }
    // Subnormal and tiny direction components (valid rays; 1/d overflows to the ±2^80 clamp).
    for (const glm::vec3 d : {glm::vec3(1e-45f, 0, 0), glm::vec3(1e-45f, 1, 0),
                              glm::vec3(1e-38f, -1e-38f, 1e-30f), glm::vec3(1, 1e-40f, -1e-40f)})
      g.rays.push_back({P({0, 0.5, 5}), 0.0f, d, kInf});
    for (int i = 0; i < 200; ++i) {  // random origins, a random axis zeroed (or two)
      glm::vec3 d = glm::vec3(random_dir());
      d[i % 3] = 0.0f;
      if (i % 4 == 0) d[(i + 1) % 3] = 0.0f;
      if (d == glm::vec3(0.0f)) d = {0, 0, 1};
      g.rays.push_back({P(glm::dvec3(u(rng), u(rng), u(rng)) * 5.0), 0.0f, d, kInf});
    }
    x.groups.push_back(std::move(g));
  }
  // box_faces: origins exactly on the sphere's bounding-box faces, along and across them.
  {
    RayGroup g{"box_faces", {}, RayGroup::Rule::kOracleOnly, 0, 0};
    glm::vec3 lo(kInf), hi(-kInf);
    for (int i = x.sphere_first; i < x.sphere_last; ++i)
      for (const glm::vec3& v : {s.triangles[i].v0, s.triangles[i].v1, s.triangles[i].v2}) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
      }
    const glm::vec3 c = 0.5f * (lo + hi);
    for (int a = 0; a < 3; ++a)
      for (const float face : {lo[a], hi[a]})
        for (int i = 0; i < 12; ++i) {
          glm::vec3 o = c + 0.9f * (hi - lo) * glm::vec3(u(rng), u(rng), u(rng)) * 0.5f;
          o[a] = face;
          glm::vec3 along(0.0f);
          along[(a + 1 + i % 2) % 3] = i % 3 == 0 ? -1.0f : 1.0f;  // in the face's plane
          g.rays.push_back({o, 0.0f, along, kInf});
          glm::vec3 across(0.0f);
          across[a] = face == lo[a] ? 1.0f : -1.0f;  // into the box
          g.rays.push_back({o, 0.0f, across + 0.1f * glm::vec3(random_dir()), kInf});
        }
    x.groups.push_back(std::move(g));
  }
  // on_surface: origins on sphere vertices and edge midpoints, inward, outward, tangent.
  {
    RayGroup g{"on_surface", {}, RayGroup::Rule::kOracleOnly, 0, 0};
    const glm::vec3 centre = P({0, 0, 0});
    for (int i = x.sphere_first; i < x.sphere_last; i += 3) {
      const Triangle& t = s.triangles[i];
      for (const glm::vec3 o : {t.v0, 0.5f * (t.v1 + t.v2)}) {
        g.rays.push_back({o, 0.0f, centre - o, kInf});
        g.rays.push_back({o, 0.0f, o - centre, kInf});
        g.rays.push_back({o, 0.0f, glm::cross(o - centre, glm::vec3(0, 1, 0.1f)), kInf});
      }
    }
    x.groups.push_back(std::move(g));
  }
  // grazing: onto the floor at angles 1e-1 .. 1e-6 rad, along x and diagonally.
  {
    RayGroup g{"grazing", {}, RayGroup::Rule::kOracleOnly, 0, 0};
    for (int k = 1; k <= 6; ++k) {
      const double th = std::pow(10.0, -k);
      for (const glm::dvec2 dir2 :
           {glm::dvec2(1, 0), glm::dvec2(0.6, 0.8), glm::dvec2(-0.8, 0.6)}) {
        const double L = 3.0;  // hits ~3 units from the start, inside the floor
        const glm::dvec3 target(-3.5 + 0.3 * k, -2, 3.2 - 0.4 * k);
        const glm::dvec3 d(dir2.x * std::cos(th), -std::sin(th), dir2.y * std::cos(th));
        const glm::dvec3 o = target - L * d;
        g.rays.push_back(ray_between(P(o), P(target + 0.5 * d)));
      }
    }
    x.groups.push_back(std::move(g));
  }
  // tiny: at the tiny triangles' centroids from several directions.
  {
    RayGroup g{"tiny", {}, RayGroup::Rule::kOracleOnly, 0, 0};
    for (std::size_t i = 0; i < s.triangles.size(); ++i) {
      const Triangle& t = s.triangles[i];
      if (glm::length(t.v1 - t.v0) > 1e-5f * static_cast<float>(frame.scale)) continue;
      const glm::vec3 c = (t.v0 + t.v1 + t.v2) / 3.0f;
      for (const glm::dvec3 from :
           {glm::dvec3(-3, 1, 5), glm::dvec3(-3, 1.2, -5), glm::dvec3(0, 3, 3)})
        g.rays.push_back(ray_between(P(from), c));
    }
    x.groups.push_back(std::move(g));
  }
  // leaving_floor: points on floor triangles (inside, on edges, at vertices) offset up, leaving
  // at 1e-1 .. 1e-6 rad above the plane: must not hit the floor again.
  {
    RayGroup g{"leaving_floor", {}, RayGroup::Rule::kAvoidRange, x.floor_first, x.floor_last};
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    for (int i = x.floor_first; i < x.floor_last; i += 2) {
      const Triangle& t = s.triangles[i];
      float a = u01(rng), c = u01(rng);
      if (a + c > 1.0f) a = 1.0f - a, c = 1.0f - c;
      for (const glm::vec2 bc : {glm::vec2(a, c), glm::vec2(0.5f, 0.0f), glm::vec2(0.0f, 0.0f)}) {
        const glm::vec3 p = barycentric_point(t, bc.x, bc.y);
        const glm::vec3 o = offset_ray_origin(p, glm::vec3(0, 1, 0));
        for (int k = 1; k <= 6; ++k) {
          const float th = std::pow(10.0f, static_cast<float>(-k));
          const float phi = 6.2831853f * u01(rng);
          g.rays.push_back(
              {o,
               0.0f,
               {std::cos(th) * std::cos(phi), std::sin(th), std::cos(th) * std::sin(phi)},
               kInf});
        }
      }
    }
    x.groups.push_back(std::move(g));
  }
  // leaving_sphere: points on the sphere's outside (barycentric, on edges), offset outward,
  // leaving at 1e-1 .. 1e-6 rad above the face's plane. The sphere is convex: any hit on it is
  // a self-intersection.
  {
    RayGroup g{"leaving_sphere", {}, RayGroup::Rule::kAvoidRange, x.sphere_first, x.sphere_last};
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    for (int i = x.sphere_first; i < x.sphere_last; i += 4) {
      const Triangle& t = s.triangles[i];
      const glm::vec3 n = facing_normal(t, t.v0 - P({0, 0, 0})) * -1.0f;  // outward
      const glm::vec3 e = glm::normalize(t.v1 - t.v0);
      const glm::vec3 f = glm::cross(n, e);
      for (const glm::vec2 bc :
           {glm::vec2(0.3f, 0.3f), glm::vec2(0.5f, 0.5f), glm::vec2(0.0f, 0.5f)}) {
        const glm::vec3 o = offset_ray_origin(barycentric_point(t, bc.x, bc.y), n);
        for (int k = 1; k <= 6; ++k) {
          const float th = std::pow(10.0f, static_cast<float>(-k));
          const float phi = 6.2831853f * u01(rng);
          const glm::vec3 tangent = std::cos(phi) * e + std::sin(phi) * f;
          g.rays.push_back({o, 0.0f, std::cos(th) * tangent + std::sin(th) * n, kInf});
        }
      }
    }
    x.groups.push_back(std::move(g));
  }
  return x;
}

namespace {

// A closed mesh in unit coordinates (centre at `centre`); `sag`: how far its surface lies
// inside the smooth shape it approximates at most (0 for flat faces), in units of the radius.
struct ClosedMesh {
  std::string name;
  std::vector<glm::dvec3> verts;
  std::vector<glm::ivec3> faces;
  glm::dvec3 centre{0.0};
  double sag = 0.0;
};

// Largest distance of a face centroid inside the unit sphere: the icosphere's chord sag.
double sphere_sag(const std::vector<glm::dvec3>& verts, const std::vector<glm::ivec3>& faces) {
  double sag = 0.0;
  for (const auto& f : faces)
    sag = std::max(sag, 1.0 - glm::length((verts[f.x] + verts[f.y] + verts[f.z]) / 3.0));
  return sag;
}

// Float spacing (one ulp) at the largest coordinate magnitude of the frame's meshes.
double float_spacing(const LeakFrame& frame) {
  const double m = std::max({std::abs(frame.offset.x), std::abs(frame.offset.y),
                             std::abs(frame.offset.z)}) + 4.0 * frame.radius;
  const float f = static_cast<float>(m);
  return static_cast<double>(std::nextafter(f, kInf)) - f;
}

// box_on_face (extreme_cases.h): from every edge midpoint (on the face plane: both ends share
// the face's coordinate) to the neighbours of the edge's first end.
RayGroup on_face_rays(const ClosedMesh& m, const std::vector<std::pair<int, int>>& edges,
                      const std::vector<std::vector<int>>& neighbours,
                      const std::vector<glm::vec3>& v) {
  RayGroup g{m.name + "_on_face", {}, RayGroup::Rule::kOracleOnly, 0, 0};
  for (const auto& e : edges) {
    const glm::vec3 o = 0.5f * (v[e.first] + v[e.second]);
    for (const int k : neighbours[e.first]) push_valid(g.rays, ray_between(o, v[k]));
  }
  return g;
}

// Adds the mesh's triangles and its ray groups (see extreme_cases.h).
void add_leak_mesh(const LeakFrame& frame, const ClosedMesh& m, LeakScene& x) {
  const Frame place{frame.name, frame.radius, frame.offset};
  Builder b{place, x.scene};
  const int first = static_cast<int>(x.scene.triangles.size());
  std::set<std::pair<int, int>> edge_set;
  for (const auto& f : m.faces) {
    b.add(m.centre + m.verts[f.x], m.centre + m.verts[f.y], m.centre + m.verts[f.z]);
    for (const auto& e : {std::minmax(f.x, f.y), std::minmax(f.y, f.z), std::minmax(f.z, f.x)})
      edge_set.insert(e);
  }
  const int last = static_cast<int>(x.scene.triangles.size());
  std::vector<glm::vec3> v;
  for (const auto& p : m.verts) v.push_back(b.place(m.centre + p));
  const std::vector<std::pair<int, int>> edges(edge_set.begin(), edge_set.end());
  auto mid = [&](const std::pair<int, int>& e) { return 0.5f * (v[e.first] + v[e.second]); };

  auto group = [&](const std::string& what) {
    return RayGroup{m.name + "_" + what, {}, RayGroup::Rule::kHitRange, first, last};
  };
  auto from_point = [&](const glm::dvec3& unit_origin) {
    RayGroup g = group(unit_origin == glm::dvec3(0.0) ? "centre" : "off_centre");
    const glm::vec3 o = b.place(m.centre + unit_origin);
    for (const glm::vec3& p : v) g.rays.push_back(ray_between(o, p));
    for (const auto& e : edges) g.rays.push_back(ray_between(o, mid(e)));
    return g;
  };
  x.groups.push_back(from_point(glm::dvec3(0.0)));
  x.groups.push_back(from_point(glm::dvec3(0.3, -0.2, 0.1)));

  // Near the surface: `inset` towards the centre from a float surface point.
  const double inset = 1.5 * m.sag * frame.radius + 8.0 * float_spacing(frame);
  const glm::dvec3 centre = glm::dvec3(b.place(m.centre));
  auto under = [&](const glm::vec3& p) {
    const glm::dvec3 q(p);
    return glm::vec3(q + glm::normalize(centre - q) * inset);
  };
  RayGroup g = group("near_surface");
  std::vector<std::vector<int>> neighbours(v.size());
  for (const auto& e : edges) {
    neighbours[e.first].push_back(e.second);
    neighbours[e.second].push_back(e.first);
    g.rays.push_back(ray_between(under(mid(e)), mid(e)));
  }
  for (std::size_t i = 0; i < v.size(); ++i) {
    const glm::vec3 o = under(v[i]);
    g.rays.push_back(ray_between(o, v[i]));
    for (const int k : neighbours[i]) g.rays.push_back(ray_between(o, v[k]));
  }
  x.groups.push_back(std::move(g));
  if (m.sag == 0.0) x.groups.push_back(on_face_rays(m, edges, neighbours, v));
}

}  // namespace

std::vector<LeakFrame> leak_frames() {
  return {{"at_origin", 1.0, {0, 0, 0}},
          {"translated_1e2", 1.0, {1e2, -1e2, 1e2}},
          {"translated_1e4", 1.0, {1e4, -1e4, 1e4}},
          {"translated_1e6", 100.0, {1e6, 1e6, -1e6}}};
}

LeakScene make_leak_scene(const LeakFrame& frame) {
  LeakScene x;
  x.frame = frame;
  x.scene.name = "leak-" + frame.name;
  x.scene.materials.emplace_back();
  ClosedMesh sphere{"sphere", {}, {}, glm::dvec3(0.0), 0.0};
  icosphere(4, sphere.verts, sphere.faces);
  sphere.sag = sphere_sag(sphere.verts, sphere.faces);
  add_leak_mesh(frame, sphere, x);
  ClosedMesh box{"box", {}, {}, glm::dvec3(3, 0, 0), 0.0};
  box_grid(16, box.verts, box.faces);
  add_leak_mesh(frame, box, x);
  return x;
}

std::vector<gpu::Ray> group_rays(const std::vector<RayGroup>& groups) {
  std::vector<gpu::Ray> rays;
  for (const RayGroup& g : groups) rays.insert(rays.end(), g.rays.begin(), g.rays.end());
  return rays;
}

int count_rule_breaks(const std::vector<RayGroup>& groups, std::span<const gpu::Hit> hits) {
  int breaks = 0;
  std::size_t i = 0;
  for (const RayGroup& g : groups)
    for (std::size_t k = 0; k < g.rays.size(); ++k, ++i) {
      const bool in_range = hits[i].prim >= g.first && hits[i].prim < g.last;
      breaks += (g.rule == RayGroup::Rule::kHitRange && !in_range) ||
                (g.rule == RayGroup::Rule::kAvoidRange && in_range);
    }
  return breaks;
}

std::vector<gpu::Ray> extreme_rays(const ExtremeScene& x, const glm::vec3& centre) {
  std::vector<gpu::Ray> rays = group_rays(x.groups);
  const std::vector<gpu::Ray> invalid = invalid_rays(centre);
  rays.insert(rays.end(), invalid.begin(), invalid.end());
  return rays;
}

int count_extreme_failures(const ExtremeScene& x, std::span<const gpu::Hit> hits) {
  int failures = x.huge ? 0 : count_rule_breaks(x.groups, hits);
  std::size_t grouped = 0;
  for (const RayGroup& g : x.groups) grouped += g.rays.size();
  for (std::size_t i = grouped; i < hits.size(); ++i) failures += hits[i].prim != -1;
  return failures;
}

std::vector<gpu::Ray> invalid_rays(const glm::vec3& inside) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = kInf;
  const glm::vec3 o = inside;
  return {
      {{nan, o.y, o.z}, 0, {0, 0, 1}, inf},
      {{o.x, -inf, o.z}, 0, {0, 0, 1}, inf},
      {{inf, inf, inf}, 0, {1, 1, 1}, inf},
      {o, 0, {nan, 0, 1}, inf},
      {o, 0, {0, inf, 0}, inf},
      {o, 0, {-inf, -inf, -inf}, inf},
      {o, 0, {nan, nan, nan}, inf},
      {o, 0, {0, 0, 0}, inf},
      {o, 0, {-0.0f, 0.0f, -0.0f}, inf},
      {o, nan, {0, 0, 1}, inf},
      {o, 0, {0, 0, 1}, nan},
      {o, inf, {0, 0, 1}, inf},
      {o, 1.0f, {0, 0, 1}, 0.5f},
      {o, 0, {0, 0, 1}, -inf},
  };
}

}  // namespace hrpp::test
