// Nodes of at most kMaxSmallNode references, where most of the bins would be empty: the SAH split
// is evaluated over the references themselves, sorted by bin on each axis, and they are
// partitioned from a copy. The split is the one binning would find (the same axis, cost and
// boxes; the bin may differ only among boundaries with empty bins between them, which put the
// same references on each side).
#pragma once

#include <cstdint>

#include "bvh/sah_bins.h"

namespace hrpp::bvh_build {

constexpr std::uint32_t kMaxSmallNode = 8;

// Two references: binning puts the lower centroid in bin 0 and the higher in the last bin on
// every axis with extent, so the split is the first such axis, at cost A_0 + A_1, the lower
// one left. Returns the split (axis -1: none) and puts the left reference first.
Split split_pair(PrimRef* refs, const Box4& centroids, float parent_area,
                 const BvhConfig& config);

class SmallNode {
 public:
  // Copies refs[0, n), n <= kMaxSmallNode, with their boxes, centroids and bins.
  void load(const PrimRef* refs, std::uint32_t n, const BinMap& map);
  // The cheapest split as best_split over the bins would give it (axis -1: none).
  Split best_split(const Box4& centroids, float parent_area, const BvhConfig& config);
  // Writes the references back to refs[0, n): the split's left side first, each side in the
  // loaded order. Returns the left count.
  std::uint32_t partition(PrimRef* refs, const Split& split) const;

 private:
  void sort();
  void sides(Split& split) const;

  std::uint32_t n_ = 0;
  PrimRef ref_[kMaxSmallNode];
  Box4 box_[kMaxSmallNode];
  simd::Float4 centroid_[kMaxSmallNode];
  alignas(16) std::int32_t bin_[kMaxSmallNode][4];
  std::uint8_t order_[3][kMaxSmallNode];  // per axis: references by bin, stable
};

}  // namespace hrpp::bvh_build
