// A polygon face (OBJ's `f` of four or more corners) as triangles.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace hrpp {

// Index triples into `corners` (a polygon's corners in order, wound as its face), each wound as
// the polygon: a fan from corner 0 when the polygon is convex, ear clipping on the plane of its
// Newell normal otherwise (a polygon with no ear left, self-intersecting or degenerate, ends as
// a fan of what remains).
std::vector<std::uint32_t> triangulate_polygon(const std::vector<glm::vec3>& corners);

}  // namespace hrpp
