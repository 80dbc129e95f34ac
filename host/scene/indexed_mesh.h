// An indexed triangle mesh in its own (object) space, as the OBJ, PLY and pbrt readers and the
// shape tessellators produce it before it is placed in a Scene (scene_builder.h).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

namespace hrpp {

struct IndexedMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;        // empty, or one per position
  std::vector<glm::vec2> uvs;            // empty, or one per position
  std::vector<std::uint32_t> indices;    // three per triangle, counter-clockwise = front
  std::vector<std::uint32_t> materials;  // empty (all 0), or one per triangle

  std::size_t triangle_count() const { return indices.size() / 3; }
};

}  // namespace hrpp
