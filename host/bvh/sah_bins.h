// The binned SAH builder's data (Wald 2007, "On fast Construction of SAH-based Bounding Volume
// Hierarchies"): 32-byte primitive references, boxes as SIMD lanes, centroid bins per axis kept
// as separate arrays of lower corners, upper corners and counts, and the SAH sweep over them
// with the three axes in lanes.
#pragma once

#include <bit>
#include <cstdint>
#include <limits>

#include "bvh/aabb.h"
#include "bvh/bvh.h"
#include "bvh/simd4.h"

namespace hrpp::bvh_build {

constexpr int kMaxBins = 64;

// A triangle while the tree is built: its box and id, 32 bytes, partitioned in place. The id's
// bits sit in lo[3] (loads zero that lane), hi[3] is 0.
struct PrimRef {
  float lo[4];
  float hi[4];
  std::uint32_t id() const { return std::bit_cast<std::uint32_t>(lo[3]); }
  void set(simd::Float4 l, simd::Float4 h, std::uint32_t triangle) {
    simd::store(lo, l);
    simd::store(hi, h);
    lo[3] = std::bit_cast<float>(triangle);
  }
  simd::Float4 lo4() const { return simd::load3(lo); }
  simd::Float4 hi4() const { return simd::load3(hi); }
  // The centroid as Aabb::center() computes it: 0.5 (lo + hi).
  simd::Float4 centroid() const { return simd::splat3(0.5f) * (lo4() + hi4()); }
};
static_assert(sizeof(PrimRef) == 32);

struct Box4 {
  simd::Float4 lo = simd::splat3(std::numeric_limits<float>::infinity());
  simd::Float4 hi = simd::splat3(-std::numeric_limits<float>::infinity());
  void grow(simd::Float4 p) {
    lo = simd::min(lo, p);
    hi = simd::max(hi, p);
  }
  void grow(const Box4& b) {
    lo = simd::min(lo, b.lo);
    hi = simd::max(hi, b.hi);
  }
  float area() const { return simd::area(lo, hi); }  // of a non-empty box
  float extent(int axis) const { return simd::lane(hi, axis) - simd::lane(lo, axis); }
  Aabb aabb() const {
    alignas(16) float l[4], h[4];
    simd::store(l, lo);
    simd::store(h, hi);
    Aabb b;
    b.lo = {l[0], l[1], l[2]};
    b.hi = {h[0], h[1], h[2]};
    return b;
  }
};

// Centroid → bin per axis over a node's centroid bounds: trunc(clamp((c - lo) scale, 0, n - 1))
// with scale = n / extent (0 on an axis without extent, where every centroid is in bin 0).
class BinMap {
 public:
  BinMap(const Box4& centroids, int bins);
  int bins() const { return bins_; }
  void map(simd::Float4 c, std::int32_t out[4]) const {
    simd::truncate(simd::min(simd::max(position(c), simd::splat3(0.0f)), top_), out);
  }
  // (c - lo) scale: the bin before clamping and truncation. Its bin is <= k < bins - 1 exactly
  // when this is < k + 1 (the same floats, so the same answer as map).
  simd::Float4 position(simd::Float4 c) const { return (c - lo_) * scale_; }

 private:
  simd::Float4 lo_, scale_, top_;
  int bins_;
};

// Bins of one node (or of one thread's share of it) on the three axes: per axis and bin the
// box's corners as vectors (one min and one max per reference), the counts with the axes as
// lanes (loaded as one vector in the sweep).
struct SahBins {
  simd::Float4 lo[3][kMaxBins];
  simd::Float4 hi[3][kMaxBins];
  alignas(16) std::uint32_t count[kMaxBins][4];

  void clear(int bins);
  void add(const PrimRef* refs, std::uint32_t n, const BinMap& map);
  // The same, with every other reference binned into `odd` and merged after: two independent
  // chains of updates where consecutive references fall in the same bins.
  void add(const PrimRef* refs, std::uint32_t n, const BinMap& map, SahBins& odd);
  [[gnu::always_inline]] void add(const PrimRef& r, const BinMap& map) {
    const simd::Float4 l = r.lo4(), h = r.hi4();
    alignas(16) std::int32_t b[4];
    map.map(simd::splat3(0.5f) * (l + h), b);
    grow(0, b[0], l, h);
    grow(1, b[1], l, h);
    grow(2, b[2], l, h);
  }
  void merge(const SahBins& other, int bins);  // exact: min, max and sums
  Box4 box(int axis, int first, int last) const;  // union of bins [first, last] on `axis`
  [[gnu::always_inline]] void grow(int axis, int bin, simd::Float4 l, simd::Float4 h) {
    lo[axis][bin] = simd::min(lo[axis][bin], l);
    hi[axis][bin] = simd::max(hi[axis][bin], h);
    ++count[bin][axis];
  }
};

struct Split {
  int axis = -1;  // -1: no plane separates the centroids
  int bin = 0;    // the left side takes bins [0, bin]
  float cost = 0.0f;  // Ct + Ci (A_l N_l + A_r N_r) / A_parent
  Box4 left, right;   // the children's bounds
  // The children's centroid bounds, when the split had them at hand (small nodes, pairs).
  bool has_centroids = false;
  Box4 left_centroids, right_centroids;
};

// The cheapest plane by the SAH, scanning axes x, y, z and bins left to right (the first of
// equal costs wins). Axes whose centroid extent is 0 are skipped.
Split best_split(const SahBins& bins, const BinMap& map, const Box4& centroids,
                 float parent_area, const BvhConfig& config);

// From per-axis lanes of the cheapest costs (A_l N_l + A_r N_r) and their bins: the first axis
// of the cheapest cost (x, y, z), its bin and that cost (axis -1 when every lane is infinite).
Split pick_axis(simd::Float4 cost, simd::Int4 bin);
// Sets best.cost = Ct + Ci best_cost / parent_area (best_cost = A_l N_l + A_r N_r).
void finish_split(Split& best, float best_cost, float parent_area, const BvhConfig& config);

// Boxes of three axes' candidates (bins, or references of a small node) with axis a in lane a:
// corners by component, so one pass of vector operations sweeps the three axes.
struct LaneBoxes {
  simd::Float4 lx, ly, lz, hx, hy, hz;

  static LaneBoxes empty() {
    const Box4 e;
    return {e.lo, e.lo, e.lo, e.hi, e.hi, e.hi};
  }
  // From the boxes [lo0, hi0] (axis x), [lo1, hi1] (y) and [lo2, hi2] (z).
  static LaneBoxes of(simd::Float4 lo0, simd::Float4 lo1, simd::Float4 lo2, simd::Float4 hi0,
                      simd::Float4 hi1, simd::Float4 hi2) {
    LaneBoxes b;
    simd::transpose3(lo0, lo1, lo2, b.lx, b.ly, b.lz);
    simd::transpose3(hi0, hi1, hi2, b.hx, b.hy, b.hz);
    return b;
  }
  void grow(const LaneBoxes& b) {
    lx = simd::min(lx, b.lx), ly = simd::min(ly, b.ly), lz = simd::min(lz, b.lz);
    hx = simd::max(hx, b.hx), hy = simd::max(hy, b.hy), hz = simd::max(hz, b.hz);
  }
  simd::Float4 area() const { return simd::area(hx - lx, hy - ly, hz - lz); }
};

}  // namespace hrpp::bvh_build
