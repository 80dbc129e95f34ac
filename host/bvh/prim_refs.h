// The builders' starting point: one reference (box and id) per non-degenerate triangle of a
// scene, in id order, with the references' bounds and centroid bounds.
#pragma once

#include <cstdint>
#include <memory>

#include "bvh/sah_bins.h"
#include "common/task_pool.h"
#include "scene/scene.h"

namespace hrpp::bvh_build {

struct References {
  std::unique_ptr<PrimRef[]> refs;  // default-initialised: the threads that fill it fault it in
  std::uint32_t count = 0;
  Box4 bounds, centroids;
  std::uint32_t degenerate = 0;
};

// In parallel chunks on the pool. Boxes get +0.0f added, which turns -0 into +0: min and max
// then give the same bits in any order.
References make_references(const Scene& scene, TaskPool& pool);

}  // namespace hrpp::bvh_build
