// append_mesh(): an IndexedMesh placed in world space, as scene_builder.h describes.
#include "scene/scene_builder.h"

#include <cmath>
#include <utility>
#include <vector>

#include "common/error.h"

namespace hrpp {
namespace {

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::vector<glm::vec3> world_positions(const IndexedMesh& mesh, const glm::dmat4& m,
                                       const std::string& where) {
  std::vector<glm::vec3> wp(mesh.positions.size());
  for (std::size_t i = 0; i < wp.size(); ++i) {
    const glm::dvec3 p(mesh.positions[i]);
    if (!finite(p)) {
      throw Error(where + ": vertex " + std::to_string(i) +
                  " has a non-finite coordinate (NaN or Inf)");
    }
    const glm::dvec3 w(m * glm::dvec4(p, 1.0));
    wp[i] = glm::vec3(w);
    if (!finite(glm::dvec3(wp[i]))) {
      throw Error(where + ": vertex " + std::to_string(i) +
                  " is out of float range after its transform");
    }
  }
  return wp;
}

std::vector<glm::vec3> world_normals(const IndexedMesh& mesh, const glm::dmat4& m) {
  std::vector<glm::vec3> wn(mesh.normals.size());
  const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(m)));
  for (std::size_t i = 0; i < wn.size(); ++i) {
    const glm::dvec3 n = normal_matrix * glm::dvec3(mesh.normals[i]);
    const double len = glm::length(n);
    wn[i] = (len > 0.0 && std::isfinite(len)) ? glm::vec3(n / len) : glm::vec3(0.0f);
  }
  return wn;
}

}  // namespace

void check_mesh(const IndexedMesh& mesh, const std::string& where) {
  const std::size_t nv = mesh.positions.size();
  if (mesh.indices.size() % 3 != 0) {
    throw Error(where + ": " + std::to_string(mesh.indices.size()) +
                " indices, not a multiple of 3");
  }
  if (!mesh.normals.empty() && mesh.normals.size() != nv) {
    throw Error(where + ": " + std::to_string(mesh.normals.size()) + " normals for " +
                std::to_string(nv) + " vertices");
  }
  if (!mesh.uvs.empty() && mesh.uvs.size() != nv) {
    throw Error(where + ": " + std::to_string(mesh.uvs.size()) + " uvs for " + std::to_string(nv) +
                " vertices");
  }
  if (!mesh.materials.empty() && mesh.materials.size() != mesh.triangle_count()) {
    throw Error(where + ": " + std::to_string(mesh.materials.size()) + " materials for " +
                std::to_string(mesh.triangle_count()) + " triangles");
  }
  for (std::size_t e = 0; e < mesh.indices.size(); ++e) {
    if (mesh.indices[e] >= nv) {
      throw Error(where + ": vertex index " + std::to_string(mesh.indices[e]) +
                  " is out of range (" + std::to_string(nv) + " vertices)");
    }
  }
}

void append_mesh(Scene& scene, const IndexedMesh& mesh, const MeshPlacement& placement,
                 const std::string& where) {
  check_mesh(mesh, where);
  const std::size_t nt = mesh.triangle_count();
  if (nt > kMaxSceneTriangles - scene.triangles.size()) {
    throw Error(where + ": more than " + std::to_string(kMaxSceneTriangles) + " triangles");
  }
  const std::vector<glm::vec3> wp = world_positions(mesh, placement.object_to_world, where);
  const std::vector<glm::vec3> wn = world_normals(mesh, placement.object_to_world);
  for (std::size_t t = 0; t < nt; ++t) {
    std::uint32_t k[3] = {mesh.indices[3 * t], mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]};
    if (placement.flip_winding) std::swap(k[1], k[2]);
    scene.triangles.push_back(Triangle{wp[k[0]], wp[k[1]], wp[k[2]]});
    TriangleShading s;
    if (!wn.empty()) {
      s.n0 = wn[k[0]];
      s.n1 = wn[k[1]];
      s.n2 = wn[k[2]];
    }
    if (!mesh.uvs.empty()) {
      s.uv0 = mesh.uvs[k[0]];
      s.uv1 = mesh.uvs[k[1]];
      s.uv2 = mesh.uvs[k[2]];
    }
    s.material = mesh.materials.empty() ? placement.material : mesh.materials[t];
    scene.shading.push_back(s);
  }
}

}  // namespace hrpp
