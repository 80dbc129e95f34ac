// Loop subdivision as pbrt-v4's LoopSubdivide (src/pbrt/util/loopsubdiv.cpp): the control mesh
// as faces with neighbour links, refined level by level with the Loop masks, pushed to the limit
// surface, normals from the limit tangents. Faces and vertices are indices into arrays; the
// face walks, rings and masks follow pbrt's so that the order and the rounding match it.
#include "scene/loop_subdiv.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <unordered_map>

#include "common/error.h"

namespace hrpp {
namespace {

constexpr std::int32_t kNoFace = -1;
constexpr std::uint32_t kNoVertex = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kMaxTriangles = std::size_t{1} << 30;
constexpr float kPi = 3.14159265358979323846f;

int next(int i) { return (i + 1) % 3; }
int prev(int i) { return (i + 2) % 3; }

struct SubdivFace {
  std::array<std::uint32_t, 3> v{};
  // f[i]: the face across the edge v[i] -> v[next(i)], or kNoFace on a boundary.
  std::array<std::int32_t, 3> f{kNoFace, kNoFace, kNoFace};
};

struct SubdivVertex {
  glm::vec3 p{0.0f};
  std::uint32_t start_face = kNoVertex;
  bool boundary = false;
};

struct SubdivMesh {
  std::vector<SubdivVertex> vertices;
  std::vector<SubdivFace> faces;

  int vnum(std::int32_t face, std::uint32_t vertex) const {
    const SubdivFace& f = faces[static_cast<std::size_t>(face)];
    return f.v[0] == vertex ? 0 : (f.v[1] == vertex ? 1 : 2);
  }
  const SubdivFace& face(std::int32_t face) const { return faces[static_cast<std::size_t>(face)]; }
  std::int32_t next_face(std::int32_t f, std::uint32_t v) const { return face(f).f[vnum(f, v)]; }
  std::int32_t prev_face(std::int32_t f, std::uint32_t v) const {
    return face(f).f[prev(vnum(f, v))];
  }
  std::uint32_t next_vert(std::int32_t f, std::uint32_t v) const {
    return face(f).v[next(vnum(f, v))];
  }
  std::uint32_t prev_vert(std::int32_t f, std::uint32_t v) const {
    return face(f).v[prev(vnum(f, v))];
  }
  std::int32_t start(std::uint32_t v) const {
    return static_cast<std::int32_t>(vertices[v].start_face);
  }
  const glm::vec3& p(std::uint32_t v) const { return vertices[v].p; }

  // The number of neighbours of v: faces of its fan, plus one on a boundary.
  int valence(std::uint32_t v) const {
    const std::int32_t first = start(v);
    int faces_seen = 1;
    std::int32_t f = first;
    if (!vertices[v].boundary) {
      while ((f = next_face(f, v)) != first) ++faces_seen;
      return faces_seen;
    }
    while ((f = next_face(f, v)) != kNoFace) ++faces_seen;
    f = first;
    while ((f = prev_face(f, v)) != kNoFace) ++faces_seen;
    return faces_seen + 1;
  }

  // The neighbours of v in pbrt's order: interior from the start face on; boundary from one
  // boundary neighbour through the fan to the other (ring.front() and ring.back()).
  void one_ring(std::uint32_t v, std::vector<glm::vec3>& ring) const {
    ring.clear();
    std::int32_t f = start(v);
    if (!vertices[v].boundary) {
      do {
        ring.push_back(p(next_vert(f, v)));
        f = next_face(f, v);
      } while (f != start(v));
      return;
    }
    for (std::int32_t g; (g = next_face(f, v)) != kNoFace;) f = g;
    ring.push_back(p(next_vert(f, v)));
    do {
      ring.push_back(p(prev_vert(f, v)));
      f = prev_face(f, v);
    } while (f != kNoFace);
  }
};

float loop_beta(int valence) {
  return valence == 3 ? 3.0f / 16.0f : 3.0f / (8.0f * static_cast<float>(valence));
}

float loop_gamma(int valence) {
  return 1.0f / (static_cast<float>(valence) + 3.0f / (8.0f * loop_beta(valence)));
}

// p(1 - n·beta) + beta·(each neighbour), the ring already gathered.
glm::vec3 weight_one_ring(const glm::vec3& p, const std::vector<glm::vec3>& ring, float beta) {
  glm::vec3 sum = (1.0f - static_cast<float>(ring.size()) * beta) * p;
  for (const glm::vec3& q : ring) sum += beta * q;
  return sum;
}

// p(1 - 2·beta) + beta·(each boundary neighbour).
glm::vec3 weight_boundary(const glm::vec3& p, const std::vector<glm::vec3>& ring, float beta) {
  glm::vec3 sum = (1.0f - 2.0f * beta) * p;
  sum += beta * ring.front();
  sum += beta * ring.back();
  return sum;
}

std::string edge_error(const std::string& where, std::uint32_t a, std::uint32_t b,
                       const std::string& why) {
  return where + ": loopsubdiv: non-manifold edge between vertices " +
         std::to_string(std::min(a, b)) + " and " + std::to_string(std::max(a, b)) + " (" + why +
         ")";
}

void check_input(std::size_t point_count, const std::vector<std::uint32_t>& indices, int levels,
                 const std::string& where) {
  const std::string at = where + ": loopsubdiv: ";
  if (levels < 0) throw Error(at + "negative \"levels\" " + std::to_string(levels));
  if (levels > kMaxLoopLevels) {
    throw Error(at + "\"levels\" " + std::to_string(levels) + " is over the limit of " +
                std::to_string(kMaxLoopLevels));
  }
  if (indices.empty()) throw Error(at + "no triangles (\"indices\" is empty)");
  if (indices.size() % 3 != 0) {
    throw Error(at + std::to_string(indices.size()) + " indices, not a multiple of 3");
  }
  const std::size_t triangles = indices.size() / 3;
  if (triangles > (kMaxTriangles >> (2 * levels))) {
    throw Error(at + std::to_string(triangles) + " triangles at " + std::to_string(levels) +
                " levels would make more than 2^30 triangles");
  }
  for (std::size_t t = 0; t < triangles; ++t) {
    const std::uint32_t* v = &indices[3 * t];
    for (int j = 0; j < 3; ++j) {
      if (v[j] >= point_count) {
        throw Error(at + "index " + std::to_string(v[j]) + " of triangle " + std::to_string(t) +
                    " is out of range (" + std::to_string(point_count) + " points)");
      }
    }
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) {
      throw Error(at + "triangle " + std::to_string(t) + " repeats a vertex (" +
                  std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) +
                  ")");
    }
  }
}

// Links every face to its neighbours across its edges; refuses an edge used by more than two
// faces, or by two faces that run it in the same direction.
void link_neighbours(SubdivMesh& mesh, const std::string& where) {
  struct EdgeUse {
    std::uint32_t face;
    int edge;
    std::uint32_t second_face;
    int uses;
  };
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  edges.reserve(mesh.faces.size() * 2);
  for (std::uint32_t t = 0; t < mesh.faces.size(); ++t) {
    SubdivFace& face = mesh.faces[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = face.v[k], b = face.v[next(k)];
      const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
      auto [it, inserted] = edges.try_emplace(key, EdgeUse{t, k, 0, 1});
      if (inserted) continue;
      EdgeUse& use = it->second;
      if (use.uses == 2) {
        throw Error(edge_error(where, a, b,
                               "used by triangles " + std::to_string(use.face) + ", " +
                                   std::to_string(use.second_face) + " and " + std::to_string(t)));
      }
      SubdivFace& other = mesh.faces[use.face];
      if (other.v[use.edge] == a) {
        throw Error(edge_error(where, a, b,
                               "triangles " + std::to_string(use.face) + " and " +
                                   std::to_string(t) + " both run from " + std::to_string(a) +
                                   " to " + std::to_string(b) + ": inconsistent orientation"));
      }
      other.f[use.edge] = static_cast<std::int32_t>(t);
      face.f[k] = static_cast<std::int32_t>(use.face);
      use.second_face = t;
      use.uses = 2;
    }
  }
}

SubdivMesh control_mesh(const std::vector<glm::vec3>& points,
                        const std::vector<std::uint32_t>& indices, const std::string& where) {
  SubdivMesh mesh;
  mesh.vertices.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) mesh.vertices[i].p = points[i];
  mesh.faces.resize(indices.size() / 3);
  for (std::uint32_t t = 0; t < mesh.faces.size(); ++t) {
    for (int j = 0; j < 3; ++j) {
      const std::uint32_t v = indices[3 * std::size_t{t} + static_cast<std::size_t>(j)];
      mesh.faces[t].v[j] = v;
      mesh.vertices[v].start_face = t;  // the last face wins, as in pbrt
    }
  }
  link_neighbours(mesh, where);
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    if (mesh.vertices[v].start_face == kNoVertex) {
      throw Error(where + ": loopsubdiv: point " + std::to_string(v) + " is used by no triangle");
    }
    std::int32_t f = mesh.start(v);
    do {
      f = mesh.next_face(f, v);
    } while (f != kNoFace && f != mesh.start(v));
    mesh.vertices[v].boundary = f == kNoFace;
  }
  return mesh;
}

// The even vertices: each old vertex's child, at its old index.
void refine_even_vertices(const SubdivMesh& mesh, SubdivMesh& out) {
  std::vector<glm::vec3> ring;
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    const SubdivVertex& old = mesh.vertices[v];
    mesh.one_ring(v, ring);
    SubdivVertex& child = out.vertices[v];
    child.boundary = old.boundary;
    child.p = old.boundary ? weight_boundary(old.p, ring, 1.0f / 8.0f)
                           : weight_one_ring(old.p, ring, loop_beta(static_cast<int>(ring.size())));
    const std::int32_t f = mesh.start(v);
    child.start_face = 4 * old.start_face + static_cast<std::uint32_t>(mesh.vnum(f, v));
  }
}

// The odd vertex on edge k of face t.
SubdivVertex edge_vertex(const SubdivMesh& mesh, std::uint32_t t, int k) {
  const SubdivFace& face = mesh.faces[t];
  const glm::vec3& a = mesh.p(face.v[k]);
  const glm::vec3& b = mesh.p(face.v[next(k)]);
  SubdivVertex odd;
  odd.start_face = 4 * t + 3;
  odd.boundary = face.f[k] == kNoFace;
  if (odd.boundary) {
    odd.p = 0.5f * a;
    odd.p += 0.5f * b;
    return odd;
  }
  const SubdivFace& across = mesh.face(face.f[k]);
  const std::uint32_t opposite = face.v[prev(k)];
  // The neighbour runs the edge b -> a, so its third vertex follows a.
  const std::uint32_t far = across.v[next(mesh.vnum(face.f[k], face.v[k]))];
  odd.p = 3.0f / 8.0f * a;
  odd.p += 3.0f / 8.0f * b;
  odd.p += 1.0f / 8.0f * mesh.p(opposite);
  odd.p += 1.0f / 8.0f * mesh.p(far);
  return odd;
}

// One odd vertex per edge, made by the first face (in order) that has the edge; returns, per
// face and edge, the new vertex's index.
std::vector<std::array<std::uint32_t, 3>> refine_odd_vertices(const SubdivMesh& mesh,
                                                              SubdivMesh& out) {
  std::vector<std::array<std::uint32_t, 3>> odd(mesh.faces.size());
  for (std::uint32_t t = 0; t < mesh.faces.size(); ++t) {
    const SubdivFace& face = mesh.faces[t];
    for (int k = 0; k < 3; ++k) {
      const std::int32_t n = face.f[k];
      if (n != kNoFace && static_cast<std::uint32_t>(n) < t) {
        // The neighbour runs this edge from v[next(k)]: its edge number is that vertex's.
        odd[t][k] = odd[static_cast<std::size_t>(n)][mesh.vnum(n, face.v[next(k)])];
        continue;
      }
      odd[t][k] = static_cast<std::uint32_t>(out.vertices.size());
      out.vertices.push_back(edge_vertex(mesh, t, k));
    }
  }
  return odd;
}

// The child face of `neighbour` at the corner `vertex`, or kNoFace.
std::int32_t corner_child(const SubdivMesh& mesh, std::int32_t neighbour, std::uint32_t vertex) {
  if (neighbour == kNoFace) return kNoFace;
  return 4 * neighbour + mesh.vnum(neighbour, vertex);
}

// Faces 4t..4t+3: the corners at v0, v1, v2, then the middle, with their neighbour links.
void refine_faces(const SubdivMesh& mesh, const std::vector<std::array<std::uint32_t, 3>>& odd,
                  SubdivMesh& out) {
  for (std::uint32_t t = 0; t < mesh.faces.size(); ++t) {
    const SubdivFace& face = mesh.faces[t];
    SubdivFace* child = &out.faces[4 * std::size_t{t}];
    const std::int32_t base = static_cast<std::int32_t>(4 * t);
    for (int j = 0; j < 3; ++j) {
      child[3].f[j] = base + next(j);
      child[j].f[next(j)] = base + 3;
      child[j].f[j] = corner_child(mesh, face.f[j], face.v[j]);
      child[j].f[prev(j)] = corner_child(mesh, face.f[prev(j)], face.v[j]);
      child[j].v[j] = face.v[j];
      child[j].v[next(j)] = odd[t][j];
      child[next(j)].v[j] = odd[t][j];
      child[3].v[j] = odd[t][j];
    }
  }
}

SubdivMesh refine(const SubdivMesh& mesh) {
  SubdivMesh out;
  out.vertices.resize(mesh.vertices.size());
  out.vertices.reserve(mesh.vertices.size() + 3 * mesh.faces.size() / 2 + 64);
  out.faces.resize(4 * mesh.faces.size());
  refine_even_vertices(mesh, out);
  const std::vector<std::array<std::uint32_t, 3>> odd = refine_odd_vertices(mesh, out);
  refine_faces(mesh, odd, out);
  return out;
}

void push_to_limit(SubdivMesh& mesh) {
  std::vector<glm::vec3> limit(mesh.vertices.size());
  std::vector<glm::vec3> ring;
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    mesh.one_ring(v, ring);
    const glm::vec3& p = mesh.p(v);
    limit[v] = mesh.vertices[v].boundary
                   ? weight_boundary(p, ring, 1.0f / 5.0f)
                   : weight_one_ring(p, ring, loop_gamma(static_cast<int>(ring.size())));
  }
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) mesh.vertices[v].p = limit[v];
}

// a·b - c·d with the rounding error of c·d recovered, as pbrt's DifferenceOfProducts.
float difference_of_products(float a, float b, float c, float d) {
  const float cd = c * d;
  const float difference = std::fma(a, b, -cd);
  const float error = std::fma(-c, d, cd);
  return difference + error;
}

glm::vec3 cross_product(const glm::vec3& s, const glm::vec3& t) {
  return {difference_of_products(s.y, t.z, s.z, t.y), difference_of_products(s.z, t.x, s.x, t.z),
          difference_of_products(s.x, t.y, s.y, t.x)};
}

// The second limit tangent across a boundary vertex from its ring (first tangent: along it).
glm::vec3 boundary_cross_tangent(const glm::vec3& p, const std::vector<glm::vec3>& r) {
  const int valence = static_cast<int>(r.size());
  if (valence == 2) return r[0] + r[1] - 2.0f * p;
  if (valence == 3) return r[1] - p;
  if (valence == 4) return -1.0f * r[0] + 2.0f * r[1] + 2.0f * r[2] + -1.0f * r[3] + -2.0f * p;
  const float theta = kPi / static_cast<float>(valence - 1);
  glm::vec3 t = std::sin(theta) * (r[0] + r[static_cast<std::size_t>(valence - 1)]);
  for (int k = 1; k < valence - 1; ++k) {
    const float weight = (2.0f * std::cos(theta) - 2.0f) * std::sin(static_cast<float>(k) * theta);
    t += weight * r[static_cast<std::size_t>(k)];
  }
  return -t;
}

glm::vec3 limit_normal(const SubdivMesh& mesh, std::uint32_t v, std::vector<glm::vec3>& ring) {
  mesh.one_ring(v, ring);
  const int valence = static_cast<int>(ring.size());
  glm::vec3 s(0.0f), t(0.0f);
  if (!mesh.vertices[v].boundary) {
    for (int j = 0; j < valence; ++j) {
      const float angle = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(valence);
      s += std::cos(angle) * ring[static_cast<std::size_t>(j)];
      t += std::sin(angle) * ring[static_cast<std::size_t>(j)];
    }
  } else {
    s = ring.back() - ring.front();
    t = boundary_cross_tangent(mesh.p(v), ring);
  }
  return cross_product(s, t);
}

IndexedMesh to_indexed_mesh(const SubdivMesh& mesh) {
  IndexedMesh out;
  out.positions.reserve(mesh.vertices.size());
  out.normals.reserve(mesh.vertices.size());
  std::vector<glm::vec3> ring;
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    out.positions.push_back(mesh.p(v));
    out.normals.push_back(limit_normal(mesh, v, ring));
  }
  out.indices.reserve(3 * mesh.faces.size());
  for (const SubdivFace& face : mesh.faces) {
    // pbrt's (v0, v1, v2) as (v0, v2, v1): counter-clockwise toward pbrt's normals.
    out.indices.insert(out.indices.end(), {face.v[0], face.v[2], face.v[1]});
  }
  return out;
}

}  // namespace

IndexedMesh loop_subdivide(const std::vector<glm::vec3>& control_points,
                           const std::vector<std::uint32_t>& indices, int levels,
                           const std::string& where) {
  check_input(control_points.size(), indices, levels, where);
  SubdivMesh mesh = control_mesh(control_points, indices, where);
  for (int level = 0; level < levels; ++level) mesh = refine(mesh);
  push_to_limit(mesh);
  return to_indexed_mesh(mesh);
}

}  // namespace hrpp
