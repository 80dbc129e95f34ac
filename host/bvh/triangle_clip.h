// A triangle chopped at a plane perpendicular to an axis, as the boxes of its two sides: what
// spatial splits (bvh/spatial_split.h) give each side of a triangle they cut.
#pragma once

#include "bvh/aabb.h"
#include "scene/scene.h"

namespace hrpp {

struct ChoppedBoxes {
  Aabb below, above;  // empty (Aabb{}) when the triangle has no point on that side
};

// The boxes of the points p of triangle t with p[axis] <= plane and with p[axis] >= plane: the
// vertices on each side and the points where the edges cross the plane. Those are computed in
// double precision, widened by a bound on their rounding error, kept within their edge's box,
// put exactly on the plane on `axis` and rounded outward to floats. So each box contains every
// point of its side, lies inside the triangle's own box and on its side of the plane. Needs
// finite vertices.
ChoppedBoxes chop_triangle(const Triangle& t, int axis, float plane);

}  // namespace hrpp
