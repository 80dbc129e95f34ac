#include "bvh/sah_bins.h"

#include <array>

namespace hrpp::bvh_build {

using simd::Float4;
using simd::Int4;

BinMap::BinMap(const Box4& centroids, int bins) : lo_(centroids.lo), bins_(bins) {
  float scale[3];
  for (int a = 0; a < 3; ++a) {
    const float extent = centroids.extent(a);
    scale[a] = extent > 0.0f ? static_cast<float>(bins) / extent : 0.0f;
  }
  scale_ = simd::set3(scale[0], scale[1], scale[2]);
  top_ = simd::splat3(static_cast<float>(bins - 1));
}

void SahBins::clear(int bins) {
  const Box4 empty;
  for (int k = 0; k < bins; ++k) {
    for (int a = 0; a < 3; ++a) {
      lo[a][k] = centroid_lo[a][k] = empty.lo;
      hi[a][k] = centroid_hi[a][k] = empty.hi;
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
      centroid_lo[a][k] = simd::min(centroid_lo[a][k], other.centroid_lo[a][k]);
      centroid_hi[a][k] = simd::max(centroid_hi[a][k], other.centroid_hi[a][k]);
    }
    for (int a = 0; a < 4; ++a) count[k][a] += other.count[k][a];
  }
}

Box4 SahBins::box(int axis, int first, int last) const {
  Box4 b;
  for (int k = first; k <= last; ++k) b.grow(Box4{lo[axis][k], hi[axis][k]});
  return b;
}

Box4 SahBins::centroid_box(int axis, int first, int last) const {
  Box4 b;
  for (int k = first; k <= last; ++k) b.grow(Box4{centroid_lo[axis][k], centroid_hi[axis][k]});
  return b;
}

namespace {

// Boxes of one bin index on the three axes, lane a holding axis a's bin: corners by component.
struct LaneBoxes {
  Float4 lx, ly, lz, hx, hy, hz;

  static LaneBoxes empty() {
    const Box4 e;
    return {e.lo, e.lo, e.lo, e.hi, e.hi, e.hi};
  }
  static LaneBoxes of(const SahBins& bins, int k) {
    LaneBoxes b;
    simd::transpose3(bins.lo[0][k], bins.lo[1][k], bins.lo[2][k], b.lx, b.ly, b.lz);
    simd::transpose3(bins.hi[0][k], bins.hi[1][k], bins.hi[2][k], b.hx, b.hy, b.hz);
    return b;
  }
  void grow(const LaneBoxes& b) {
    lx = simd::min(lx, b.lx), ly = simd::min(ly, b.ly), lz = simd::min(lz, b.lz);
    hx = simd::max(hx, b.hx), hy = simd::max(hy, b.hy), hz = simd::max(hz, b.hz);
  }
  Float4 area() const { return simd::area(hx - lx, hy - ly, hz - lz); }
};

struct LaneBest {
  Float4 cost = simd::splat3(std::numeric_limits<float>::infinity());
  Int4 bin = simd::zero_int();
};

// For each axis (lane) the cheapest boundary k (bins [0, k] left) by A_l N_l + A_r N_r, the
// first of equal costs; boundaries with an empty side, and axes not in `valid`, cost infinity.
LaneBest sah_sweep(const SahBins& bins, int n, Float4 valid) {
  std::array<LaneBoxes, kMaxBins> boxes;
  for (int k = 0; k < n; ++k) boxes[k] = LaneBoxes::of(bins, k);
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

// References of a small node: their boxes, bins and, per axis, their order by bin.
struct SmallNode {
  std::uint32_t n;
  Box4 box[kMaxSmallNode];
  Float4 centroid[kMaxSmallNode];
  alignas(16) std::int32_t bin[kMaxSmallNode][4];
  std::uint8_t order[3][kMaxSmallNode];

  // Stable order by bin on the three axes at once: reference i goes to position
  // #{j : bin_j < bin_i, or bin_j == bin_i and j < i}, counted without branches.
  void sort() {
    for (std::uint32_t i = 0; i < n; ++i) {
      const Int4 bi = simd::load(bin[i]);
      Int4 rank = simd::zero_int();
      for (std::uint32_t j = 0; j < i; ++j) rank = rank - simd::less_equal(simd::load(bin[j]), bi);
      for (std::uint32_t j = i + 1; j < n; ++j) rank = rank - simd::less(simd::load(bin[j]), bi);
      alignas(16) std::int32_t r[4];
      simd::store(r, rank);
      for (int a = 0; a < 3; ++a) order[a][r[a]] = static_cast<std::uint8_t>(i);
    }
  }
};

// Cheapest boundary on one axis between references sorted by bin: only where the bin changes,
// in ascending bin order, strictly cheaper than best_cost (as sweep_axis over the bins).
void small_axis(const SmallNode& s, int axis, float& best_cost, Split& best) {
  const std::uint8_t* order = s.order[axis];
  float right_area[kMaxSmallNode];
  Box4 acc;
  for (std::uint32_t j = s.n - 1; j > 0; --j) {
    acc.grow(s.box[order[j]]);
    right_area[j] = acc.area();
  }
  acc = Box4{};
  for (std::uint32_t j = 0; j + 1 < s.n; ++j) {
    acc.grow(s.box[order[j]]);
    const std::int32_t bin = s.bin[order[j]][axis];
    if (bin == s.bin[order[j + 1]][axis]) continue;
    const float cost = acc.area() * static_cast<float>(j + 1) +
                       right_area[j + 1] * static_cast<float>(s.n - j - 1);
    if (cost < best_cost) {
      best_cost = cost;
      best.axis = axis;
      best.bin = bin;
    }
  }
}

void finish(Split& best, float best_cost, float parent_area, const BvhConfig& config) {
  const float inv_area = parent_area > 0.0f ? 1.0f / parent_area : 0.0f;
  best.cost = config.traversal_cost + config.intersection_cost * best_cost * inv_area;
}

}  // namespace

Split best_split_small(const PrimRef* refs, std::uint32_t n, const BinMap& map,
                       const Box4& centroids, float parent_area, const BvhConfig& config) {
  SmallNode s;
  s.n = n;
  for (std::uint32_t i = 0; i < n; ++i) {
    s.box[i] = Box4{refs[i].lo4(), refs[i].hi4()};
    s.centroid[i] = refs[i].centroid();
    map.map(s.centroid[i], s.bin[i]);
  }
  s.sort();
  Split best;
  float best_cost = std::numeric_limits<float>::infinity();
  for (int a = 0; a < 3; ++a)
    if (centroids.extent(a) > 0.0f) small_axis(s, a, best_cost, best);
  if (best.axis < 0) return best;
  finish(best, best_cost, parent_area, config);
  for (std::uint32_t i = 0; i < n; ++i) {
    const bool left = s.bin[i][best.axis] <= best.bin;
    (left ? best.left : best.right).grow(s.box[i]);
    (left ? best.left_centroids : best.right_centroids).grow(s.centroid[i]);
  }
  return best;
}

Split best_split(const SahBins& bins, const BinMap& map, const Box4& centroids,
                 float parent_area, const BvhConfig& config) {
  Float4 valid;
  {
    const Float4 zero = simd::splat3(0.0f);
    valid = simd::less(zero, centroids.hi - centroids.lo);  // extent > 0; lane 3 false
  }
  const LaneBest lanes = sah_sweep(bins, map.bins(), valid);
  alignas(16) float cost[4];
  alignas(16) std::int32_t bin[4];
  simd::store(cost, lanes.cost);
  simd::store(bin, lanes.bin);
  Split best;
  float best_cost = std::numeric_limits<float>::infinity();
  for (int a = 0; a < 3; ++a)  // x, y, z: the first axis of equal costs
    if (cost[a] < best_cost) {
      best_cost = cost[a];
      best.axis = a;
      best.bin = bin[a];
    }
  if (best.axis < 0) return best;
  finish(best, best_cost, parent_area, config);
  best.left = bins.box(best.axis, 0, best.bin);
  best.right = bins.box(best.axis, best.bin + 1, map.bins() - 1);
  best.left_centroids = bins.centroid_box(best.axis, 0, best.bin);
  best.right_centroids = bins.centroid_box(best.axis, best.bin + 1, map.bins() - 1);
  return best;
}

}  // namespace hrpp::bvh_build
