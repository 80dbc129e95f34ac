#include "bvh/sah_bins.h"

#include <array>

namespace hrpp::bvh_build {

using simd::Float4;
using simd::Int4;

// scale = bins / extent where extent > 0, else 0 (lane 3: 0).
BinMap::BinMap(const Box4& centroids, int bins) : lo_(centroids.lo), bins_(bins) {
  const Float4 extent = centroids.hi - centroids.lo, zero = simd::splat3(0.0f);
  const Float4 has_extent = simd::less(zero, extent);
  const Float4 safe = simd::select(has_extent, extent, simd::splat3(1.0f));
  scale_ = simd::select(has_extent, simd::splat3(static_cast<float>(bins)) / safe, zero);
  top_ = simd::splat3(static_cast<float>(bins - 1));
}

void SahBins::clear(int bins) {
  const Box4 empty;
  for (int k = 0; k < bins; ++k) {
    for (int a = 0; a < 3; ++a) {
      lo[a][k] = empty.lo;
      hi[a][k] = empty.hi;
    }
    for (std::uint32_t& c : count[k]) c = 0;
  }
}

// The map is copied in each: the compiler keeps a copy in registers while the bins change.
void SahBins::add(const PrimRef* refs, std::uint32_t n, const BinMap& map_in) {
  const BinMap map = map_in;
  for (std::uint32_t i = 0; i < n; ++i) add(refs[i], map);
}

void SahBins::add(const PrimRef* refs, std::uint32_t n, const BinMap& map_in, SahBins& odd) {
  const BinMap map = map_in;
  odd.clear(map.bins());
  std::uint32_t i = 0;
  for (; i + 1 < n; i += 2) {
    add(refs[i], map);
    odd.add(refs[i + 1], map);
  }
  if (i < n) add(refs[i], map);
  merge(odd, map.bins());
}

void SahBins::merge(const SahBins& other, int bins) {
  for (int k = 0; k < bins; ++k) {
    for (int a = 0; a < 3; ++a) {
      lo[a][k] = simd::min(lo[a][k], other.lo[a][k]);
      hi[a][k] = simd::max(hi[a][k], other.hi[a][k]);
    }
    for (int a = 0; a < 4; ++a) count[k][a] += other.count[k][a];
  }
}

Box4 SahBins::box(int axis, int first, int last) const {
  Box4 b;
  for (int k = first; k <= last; ++k) b.grow(Box4{lo[axis][k], hi[axis][k]});
  return b;
}


namespace {

struct LaneBest {
  Float4 cost = simd::splat3(std::numeric_limits<float>::infinity());
  Int4 bin = simd::zero_int();
};

// For each axis (lane) the cheapest boundary k (bins [0, k] left) by A_l N_l + A_r N_r, the
// first of equal costs; boundaries with an empty side, and axes not in `valid`, cost infinity.
LaneBest sah_sweep(const SahBins& bins, int n, Float4 valid) {
  std::array<LaneBoxes, kMaxBins> boxes;
  for (int k = 0; k < n; ++k)
    boxes[k] = LaneBoxes::of(bins.lo[0][k], bins.lo[1][k], bins.lo[2][k], bins.hi[0][k],
                             bins.hi[1][k], bins.hi[2][k]);
  std::array<Float4, kMaxBins> right_area;
  std::array<Int4, kMaxBins> right_count;
  LaneBoxes acc = LaneBoxes::empty();
  Int4 count = simd::zero_int();
  for (int k = n - 1; k > 0; --k) {  // bins [k, n): right of boundary k - 1
    acc.grow(boxes[k]);
    count = count + simd::load(bins.count[k]);
    right_area[k - 1] = acc.area();
    right_count[k - 1] = count;
  }
  const Float4 infinity = simd::splat3(std::numeric_limits<float>::infinity());
  LaneBest best;
  acc = LaneBoxes::empty();
  count = simd::zero_int();
  for (int k = 0; k < n - 1; ++k) {
    acc.grow(boxes[k]);
    count = count + simd::load(bins.count[k]);
    const Float4 cost = acc.area() * simd::to_float(count) +
                        right_area[k] * simd::to_float(right_count[k]);
    const Float4 ok = valid & simd::positive(count) & simd::positive(right_count[k]);
    const Float4 better = simd::less(simd::select(ok, cost, infinity), best.cost);
    best.cost = simd::select(better, cost, best.cost);
    best.bin = simd::select(better, simd::splat(k), best.bin);
  }
  return best;
}

}  // namespace

namespace {

}  // namespace

Split pick_axis(Float4 cost_lanes, Int4 bin_lanes) {
  alignas(16) float cost[4];
  alignas(16) std::int32_t bin[4];
  simd::store(cost, cost_lanes);
  simd::store(bin, bin_lanes);
  Split best;
  best.cost = std::numeric_limits<float>::infinity();
  for (int a = 0; a < 3; ++a)
    if (cost[a] < best.cost) {
      best.cost = cost[a];
      best.axis = a;
      best.bin = bin[a];
    }
  return best;
}

void finish_split(Split& best, float best_cost, float parent_area, const BvhConfig& config) {
  const float inv_area = parent_area > 0.0f ? 1.0f / parent_area : 0.0f;
  best.cost = config.traversal_cost + config.intersection_cost * best_cost * inv_area;
}

Split best_split(const SahBins& bins, const BinMap& map, const Box4& centroids,
                 float parent_area, const BvhConfig& config) {
  const Float4 valid = simd::less(simd::splat3(0.0f), centroids.hi - centroids.lo);  // extent > 0
  const LaneBest lanes = sah_sweep(bins, map.bins(), valid);
  Split best = pick_axis(lanes.cost, lanes.bin);
  const float best_cost = best.cost;
  if (best.axis < 0) return best;
  finish_split(best, best_cost, parent_area, config);
  best.left = bins.box(best.axis, 0, best.bin);
  best.right = bins.box(best.axis, best.bin + 1, map.bins() - 1);
  return best;
}

}  // namespace hrpp::bvh_build
