// SBVH builder (Stich, Friedrich and Dietrich 2009, "Spatial Splits in Bounding Volume
// Hierarchies"): at each node the binned SAH object split (bvh/sah_bins.h) and, where the
// object split's children overlap by more than BvhConfig::spatial_alpha × the root's area, the
// best spatial split (bvh/spatial_split.h); the cheaper one by the SAH wins. Spatial splits
// duplicate references, so a triangle id may sit in several leaves; each node has a budget of
// duplicates (the root's: BvhConfig::duplicate_budget × references), shared by its children in
// proportion to their references, so the total stays bounded and the tree does not depend on
// the order in which subtrees are built.
//
// The top of the tree is split level by level (the nodes of a level on the pool's threads), then
// the subtrees under N / (8 T) references are built on the pool, one thread each, largest first. The tree is the
// same for any thread count; only the numbering of Bvh::nodes and the order of prim_ids differ
// (make_gpu_layout numbers depth first, so the GPU layout is the same too).
#pragma once

#include "bvh/bvh.h"
#include "bvh/prim_refs.h"
#include "common/task_pool.h"
#include "scene/scene.h"

namespace hrpp {

// Builds over `refs` (make_references of `scene`); build_bvh calls it for BvhSplits::kSpatial.
Bvh build_sbvh(const Scene& scene, const BvhConfig& config, bvh_build::References& refs,
               TaskPool& pool);

}  // namespace hrpp
