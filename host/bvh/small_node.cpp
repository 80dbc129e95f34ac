#include "bvh/small_node.h"

#include <limits>
#include <utility>

namespace hrpp::bvh_build {

using simd::Float4;
using simd::Int4;

Split split_pair(PrimRef* refs, const Box4& centroids, float parent_area,
                 const BvhConfig& config) {
  Split best;
  int axis = 0;
  while (axis < 3 && !(centroids.extent(axis) > 0.0f)) ++axis;
  if (axis == 3) return best;
  const Box4 a{refs[0].lo4(), refs[0].hi4()}, b{refs[1].lo4(), refs[1].hi4()};
  const float cost = a.area() * 1.0f + b.area() * 1.0f;
  if (!(cost < std::numeric_limits<float>::infinity())) return best;
  const Float4 ca = refs[0].centroid(), cb = refs[1].centroid();
  const bool swap = simd::lane(cb, axis) < simd::lane(ca, axis);
  if (swap) std::swap(refs[0], refs[1]);
  best.axis = axis;
  best.bin = 0;
  finish_split(best, cost, parent_area, config);
  best.left = swap ? b : a;
  best.right = swap ? a : b;
  best.has_centroids = true;
  best.left_centroids = Box4{swap ? cb : ca, swap ? cb : ca};
  best.right_centroids = Box4{swap ? ca : cb, swap ? ca : cb};
  return best;
}

void SmallNode::load(const PrimRef* refs, std::uint32_t n, const BinMap& map) {
  n_ = n;
  for (std::uint32_t i = 0; i < n; ++i) {
    ref_[i] = refs[i];
    box_[i] = Box4{refs[i].lo4(), refs[i].hi4()};
    centroid_[i] = refs[i].centroid();
    map.map(centroid_[i], bin_[i]);
  }
  sort();
}

// Stable order by bin on the three axes at once: reference i goes to position
// #{j : bin_j < bin_i, or bin_j == bin_i and j < i}, counted without branches.
void SmallNode::sort() {
  for (std::uint32_t i = 0; i < n_; ++i) {
    const Int4 bi = simd::load(bin_[i]);
    Int4 rank = simd::zero_int();
    for (std::uint32_t j = 0; j < i; ++j) rank = rank - simd::less_equal(simd::load(bin_[j]), bi);
    for (std::uint32_t j = i + 1; j < n_; ++j) rank = rank - simd::less(simd::load(bin_[j]), bi);
    alignas(16) std::int32_t r[4];
    simd::store(r, rank);
    for (int a = 0; a < 3; ++a) order_[a][r[a]] = static_cast<std::uint8_t>(i);
  }
}

// The three axes in lanes, as the bins' sweep: boundary j (references [0, j] left in each axis's
// order) is a candidate only where the bin changes; per lane the first cheapest one wins.
Split SmallNode::best_split(const Box4& centroids, float parent_area, const BvhConfig& config) {
  LaneBoxes step[kMaxSmallNode];
  alignas(16) std::int32_t bin[kMaxSmallNode][4];  // the bin of each axis's j-th reference
  for (std::uint32_t j = 0; j < n_; ++j) {
    const std::uint8_t x = order_[0][j], y = order_[1][j], z = order_[2][j];
    step[j] = LaneBoxes::of(box_[x].lo, box_[y].lo, box_[z].lo, box_[x].hi, box_[y].hi, box_[z].hi);
    bin[j][0] = bin_[x][0], bin[j][1] = bin_[y][1], bin[j][2] = bin_[z][2], bin[j][3] = 0;
  }
  Float4 right_area[kMaxSmallNode];
  LaneBoxes acc = LaneBoxes::empty();
  for (std::uint32_t j = n_ - 1; j > 0; --j) {
    acc.grow(step[j]);
    right_area[j] = acc.area();
  }
  const Float4 infinity = simd::splat3(std::numeric_limits<float>::infinity());
  const Float4 valid = simd::less(simd::splat3(0.0f), centroids.hi - centroids.lo);
  Float4 best_cost = infinity;
  Int4 best_bin = simd::zero_int();
  acc = LaneBoxes::empty();
  for (std::uint32_t j = 0; j + 1 < n_; ++j) {
    acc.grow(step[j]);
    const Int4 here = simd::load(bin[j]);
    const Float4 cost = acc.area() * simd::splat3(static_cast<float>(j + 1)) +
                        right_area[j + 1] * simd::splat3(static_cast<float>(n_ - j - 1));
    const Float4 ok = valid & simd::as_float(simd::less(here, simd::load(bin[j + 1])));
    const Float4 better = simd::less(simd::select(ok, cost, infinity), best_cost);
    best_cost = simd::select(better, cost, best_cost);
    best_bin = simd::select(better, here, best_bin);
  }
  Split best = pick_axis(best_cost, best_bin);
  if (best.axis < 0) return best;
  finish_split(best, best.cost, parent_area, config);
  sides(best);
  return best;
}

// The children's boxes and centroid bounds (side 0 left, 1 right: no branch on the side).
void SmallNode::sides(Split& split) const {
  Box4 box[2], centroid[2];
  for (std::uint32_t i = 0; i < n_; ++i) {
    const int right = bin_[i][split.axis] > split.bin;
    box[right].grow(box_[i]);
    centroid[right].grow(centroid_[i]);
  }
  split.left = box[0], split.right = box[1];
  split.has_centroids = true;
  split.left_centroids = centroid[0], split.right_centroids = centroid[1];
}

std::uint32_t SmallNode::partition(PrimRef* refs, const Split& split) const {
  std::uint32_t left = 0;
  for (std::uint32_t i = 0; i < n_; ++i) left += bin_[i][split.axis] <= split.bin;
  std::uint32_t next[2] = {0, left};  // where the next left / right reference goes
  for (std::uint32_t i = 0; i < n_; ++i) {
    const int right = bin_[i][split.axis] > split.bin;
    refs[next[right]++] = ref_[i];
  }
  return left;
}

}  // namespace hrpp::bvh_build
