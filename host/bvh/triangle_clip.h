// The part of a triangle between two planes perpendicular to an axis, as a box: what spatial
// splits (bvh/spatial_split.h) give each side of a triangle they cut.
#pragma once

#include "bvh/aabb.h"
#include "scene/scene.h"

namespace hrpp {

// The box of the points p of triangle t with lo <= p[axis] <= hi: the triangle's polygon
// chopped at both planes (Sutherland-Hodgman) in double precision, each new vertex widened by a
// bound on its rounding error and kept within its edge's box, rounded outward to floats. So the
// box contains every such point, lies inside the triangle's own box and within [lo, hi] on
// `axis`. Empty (Aabb{}) when no point of the triangle lies between the planes. Needs finite
// vertices; lo and hi may be infinite.
Aabb clipped_box(const Triangle& t, int axis, float lo, float hi);

}  // namespace hrpp
