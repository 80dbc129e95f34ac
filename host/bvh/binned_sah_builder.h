// Binned SAH builder (Wald 2007, "On fast Construction of SAH-based Bounding Volume
// Hierarchies"): centroids binned per axis, the cheapest plane by the surface area heuristic.
#pragma once

#include "bvh/bvh.h"
#include "scene/scene.h"

namespace hrpp {

// Builds over the scene's non-degenerate triangles (ids kept). The root is always an interior
// node when there are two or more triangles, so the GPU layout needs no special root leaf.
Bvh build_bvh(const Scene& scene, const BvhConfig& config = {});

}  // namespace hrpp
