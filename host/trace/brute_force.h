// Brute force over every triangle of a scene, with the same tests and tie rule as the BVH
// traversal: what the traversal must reproduce exactly.
#pragma once

#include "gpu_types.h"
#include "scene/scene.h"

namespace hrpp {

gpu::Hit brute_force_closest(const Scene& scene, const gpu::Ray& ray);
bool brute_force_any(const Scene& scene, const gpu::Ray& ray);

}  // namespace hrpp
