// Spatial splits (Stich, Friedrich and Dietrich 2009, "Spatial Splits in Bounding Volume
// Hierarchies"): a plane cuts the node's box and every triangle reference it crosses is clipped
// into a part on each side (bvh/triangle_clip.h), so the children's boxes need not overlap at
// the price of duplicated references. The planes are bin boundaries spread evenly over the
// node's box; a reference is binned into every bin its box crosses, with the box of its
// triangle's part in that bin (its vertices there and its edges' crossings of the bin's planes,
// within the reference's box), counted as entering its first bin and leaving its last.
//
// A reference goes right of plane P when its box starts at or after P, left when it ends at or
// before P, and is cut otherwise; binning and splitting both follow that rule.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "bvh/aabb.h"
#include "bvh/bvh.h"
#include "bvh/sah_bins.h"
#include "common/task_pool.h"
#include "bvh/triangle_clip.h"
#include "scene/scene.h"

namespace hrpp::bvh_build {

struct SpatialSplit {
  int axis = -1;        // -1: none
  float position = 0;   // the plane p[axis] = position
  float cost = 0;       // Ct + Ci (A_l N_l + A_r N_r) / A_parent, from the bins
  Aabb left, right;     // the sides' boxes, from the bins
  std::uint32_t left_count = 0, right_count = 0;  // references on each side, cut ones on both
};

class SpatialBins {
 public:
  // The cheapest plane by the SAH over `bins` bins per axis of `bounds` (which hold every
  // reference's box); the first axis (x, y, z) and plane of equal costs. Axes too thin for
  // distinct planes in floats are skipped. Both sides must hold a reference. With a pool, the
  // three axes are binned on its threads (the same bins).
  SpatialSplit best_split(std::span<const PrimRef> refs, const std::vector<Triangle>& tris,
                          const Box4& bounds, int bins, const BvhConfig& config,
                          TaskPool* pool = nullptr);

 private:
  bool set_planes(int axis, float lo, float hi);
  int bin_of(int axis, float x) const;
  void bin(const PrimRef& ref, const Triangle& tri, int axis);
  void bin_parts(const PrimRef& ref, const Triangle& tri, int axis, int first, int last);
  void sweep(int axis, float parent_area, const BvhConfig& config, SpatialSplit& best) const;

  int bins_ = 0;
  float plane_[3][kMaxBins + 1];  // bin k of an axis spans [plane_[k], plane_[k + 1]]
  double bins_per_unit_[3];
  Aabb parts_[3][kMaxBins];  // bin_parts' scratch, per axis: axes may be binned in parallel
  Aabb box_[3][kMaxBins];
  std::uint32_t enter_[3][kMaxBins], exit_[3][kMaxBins];
};

// Splits refs by the plane into `left` and `right` (appended, each in input order). A cut
// reference goes whole to one side instead when Stich's reference unsplitting says so (with
// `unsplit`), when cutting it would make more than `max_duplicates` duplicates in all (then to
// the side where unsplitting costs less), or when its triangle has no point on the other side
// within its box; a reference with no point on either side is dropped. Returns the duplicates
// made.
std::uint64_t split_references(std::span<const PrimRef> refs, const std::vector<Triangle>& tris,
                               const SpatialSplit& split, bool unsplit,
                               std::uint64_t max_duplicates, std::vector<PrimRef>& left,
                               std::vector<PrimRef>& right);

}  // namespace hrpp::bvh_build
