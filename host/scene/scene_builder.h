// Places an IndexedMesh in a Scene: its vertices through an object-to-world matrix (normals
// through the inverse transpose), one TriangleShading per triangle, the checks every loader
// makes (finite positions before and after the transform, the triangle limit). The OBJ, PLY and
// pbrt readers build their scenes through it; the glTF loader has its own accessor path.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>

#include "scene/indexed_mesh.h"
#include "scene/scene.h"

namespace hrpp {

// At most this many triangles in one scene (about 13 GiB of scene data), as for glTF.
inline constexpr std::size_t kMaxSceneTriangles = std::size_t{1} << 27;

struct MeshPlacement {
  glm::dmat4 object_to_world{1.0};
  std::uint32_t material = 0;  // used where the mesh has no per-triangle materials
  bool flip_winding = false;   // swap v1 and v2 of every triangle (and their shading data)
};

// Appends the mesh's triangles in index order. Throws hrpp::Error naming `where` on a
// non-finite position, an index out of range or a scene over kMaxSceneTriangles.
void append_mesh(Scene& scene, const IndexedMesh& mesh, const MeshPlacement& placement,
                 const std::string& where);

// Throws hrpp::Error naming `where` when the mesh's indices, normals, uvs or materials do not
// fit its positions (count of indices not a multiple of 3, an index out of range, ...).
void check_mesh(const IndexedMesh& mesh, const std::string& where);

}  // namespace hrpp
