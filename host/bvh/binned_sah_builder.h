// Binned SAH builder (Wald 2007, "On fast Construction of SAH-based Bounding Volume
// Hierarchies"): centroids binned per axis, the cheapest plane by the surface area heuristic.
//
// In parallel on BvhConfig::threads threads (0: all hardware threads), one fixed pool
// (common/task_pool.h): the top of the tree is split breadth first by all threads together
// (binning over chunks into per-thread bins that are merged, chunked in-place partition), then
// the nodes under N / (8 T) references are built as whole subtrees, one thread each, largest
// first, into their own node arrays, and stitched together numbered depth first as one thread
// would number them. Every step's outcome depends on the references alone (min, max and counts
// merge exactly; the partition's chunks do not depend on the thread count), so the tree,
// node ids and triangle order included, is the same for any number of threads.
//
// References are 32 bytes (box and triangle id, bvh/sah_bins.h), partitioned in place. Nodes of
// up to 8 references skip the bins (bvh/small_node.h) and nodes of two are split directly: both
// find the split that binning finds.
#pragma once

#include "bvh/bvh.h"
#include "scene/scene.h"

namespace hrpp {

// Builds over the scene's non-degenerate triangles (ids kept). The root is always an interior
// node when there are two or more triangles, so the GPU layout needs no special root leaf.
// config.splits == BvhSplits::kSpatial builds an SBVH instead (bvh/sbvh_builder.h).
Bvh build_bvh(const Scene& scene, const BvhConfig& config = {});

}  // namespace hrpp
