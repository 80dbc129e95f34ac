#include "bvh/spatial_split.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bvh/triangle_clip.h"

namespace hrpp::bvh_build {
namespace {

Aabb intersection(const Aabb& a, const Aabb& b) {
  Aabb c;
  c.lo = glm::max(a.lo, b.lo);
  c.hi = glm::min(a.hi, b.hi);
  return c;
}

Aabb united(Aabb a, const Aabb& b) {
  a.grow(b);
  return a;
}

// A reference with this box (+0.0f turns -0 into +0, as for the first references).
PrimRef make_ref(const Aabb& b, std::uint32_t id) {
  PrimRef r;
  const simd::Float4 zero = simd::splat3(0.0f);
  r.set(simd::set3(b.lo.x, b.lo.y, b.lo.z) + zero, simd::set3(b.hi.x, b.hi.y, b.hi.z) + zero, id);
  return r;
}

// The box of a reference.
Aabb ref_box(const PrimRef& ref) {
  Aabb b;
  b.lo = {ref.lo[0], ref.lo[1], ref.lo[2]};
  b.hi = {ref.hi[0], ref.hi[1], ref.hi[2]};
  return b;
}

// The parts of a reference's triangle on either side of the plane p[axis] = plane, within the
// reference's box (chop_triangle, bvh/triangle_clip.h): empty boxes for sides with no point.
ChoppedBoxes chop_reference(const PrimRef& ref, const Triangle& tri, int axis, float plane) {
  const Aabb box = ref_box(ref);
  ChoppedBoxes c = chop_triangle(tri, axis, plane);
  c.below = intersection(c.below, box);
  c.above = intersection(c.above, box);
  return c;
}

}  // namespace

// Planes lo = p_0 < p_1 < ... < p_bins = hi, evenly spread (in double, then rounded); false
// when floats cannot hold them distinct.
bool SpatialBins::set_planes(int axis, float lo, float hi) {
  float* p = plane_[axis];
  const double l = lo, extent = static_cast<double>(hi) - l;
  bins_per_unit_[axis] = extent > 0.0 ? bins_ / extent : 0.0;
  p[0] = lo;
  p[bins_] = hi;
  for (int k = 1; k < bins_; ++k) p[k] = static_cast<float>(l + extent * k / bins_);
  for (int k = 1; k <= bins_; ++k)
    if (!(p[k - 1] < p[k])) return false;
  return true;
}

// The bin of coordinate x on `axis`: the number of inner planes at or before it (from the
// even spacing, then corrected against the rounded planes).
int SpatialBins::bin_of(int axis, float x) const {
  const float* p = plane_[axis];
  const double guess = (static_cast<double>(x) - p[0]) * bins_per_unit_[axis];
  int k = static_cast<int>(std::clamp(guess, 0.0, static_cast<double>(bins_ - 1)));
  while (k > 0 && x < p[k]) --k;
  while (k < bins_ - 1 && p[k + 1] <= x) ++k;
  return k;
}

// Into bins [first, last]: first the bin of the box's start (it lies right of the planes at or
// before it), last the number of inner planes strictly before its end, at least first.
void SpatialBins::bin(const PrimRef& ref, const Triangle& tri, int axis) {
  const int first = bin_of(axis, ref.lo[axis]);
  int last = bin_of(axis, ref.hi[axis]);
  if (last > 0 && plane_[axis][last] == ref.hi[axis]) --last;  // a plane at the end: not crossed
  last = std::max(first, last);
  ++enter_[axis][first];
  ++exit_[axis][last];
  if (first == last)
    box_[axis][first].grow(ref_box(ref));
  else
    bin_parts(ref, tri, axis, first, last);
}

// Grows bins [first, last] by the parts of the triangle in them, within the reference's box:
// each part's box from the vertices in the bin and the points where the edges cross its
// planes. An estimate for the SAH (in float, rounded to nearest), which needs no more;
// split_references cuts with chop_triangle, whose boxes are conservative.
void SpatialBins::bin_parts(const PrimRef& ref, const Triangle& tri, int axis, int first,
                            int last) {
  const int n = last - first + 1;
  Aabb* part = parts_[axis];  // part[k - first]: bin k's part
  std::fill(part, part + n, Aabb{});
  const glm::vec3 v[3] = {tri.v0, tri.v1, tri.v2};
  int vb[3];  // the vertices' bins, within [first, last]
  for (int i = 0; i < 3; ++i) {
    vb[i] = std::clamp(bin_of(axis, v[i][axis]), first, last);
    part[vb[i] - first].grow(v[i]);
  }
  for (int i = 0; i < 3; ++i) {
    int lo = i, hi = (i + 1) % 3;
    if (v[lo][axis] > v[hi][axis]) std::swap(lo, hi);
    const glm::vec3 &a = v[lo], &b = v[hi];
    for (int k = vb[lo] + 1; k <= vb[hi]; ++k) {  // planes k with a < plane <= b
      const float p = plane_[axis][k];
      if (!(a[axis] < p && p < b[axis])) continue;
      glm::vec3 q = a + (p - a[axis]) / (b[axis] - a[axis]) * (b - a);
      q[axis] = p;
      if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) continue;
      part[k - 1 - first].grow(q);
      part[k - first].grow(q);
    }
  }
  const Aabb box = ref_box(ref);
  for (int k = 0; k < n; ++k) {
    const Aabb c = intersection(part[k], box);
    if (!c.empty()) box_[axis][first + k].grow(c);
  }
}

// For each inner plane k (bins [0, k) left): A_l N_l + A_r N_r, N_l counting the references
// entering left of it and N_r those leaving right of it.
void SpatialBins::sweep(int axis, float parent_area, const BvhConfig& config,
                        SpatialSplit& best) const {
  Aabb right_box[kMaxBins];
  std::uint32_t right_count[kMaxBins];
  Aabb acc;
  std::uint32_t count = 0;
  for (int k = bins_ - 1; k > 0; --k) {
    acc.grow(box_[axis][k]);
    count += exit_[axis][k];
    right_box[k] = acc;
    right_count[k] = count;
  }
  acc = Aabb{};
  count = 0;
  const float inv_area = parent_area > 0.0f ? 1.0f / parent_area : 0.0f;
  for (int k = 1; k < bins_; ++k) {
    acc.grow(box_[axis][k - 1]);
    count += enter_[axis][k - 1];
    if (count == 0 || right_count[k] == 0) continue;
    const float sum = acc.area() * static_cast<float>(count) +
                      right_box[k].area() * static_cast<float>(right_count[k]);
    const float cost = config.traversal_cost + config.intersection_cost * sum * inv_area;
    if (best.axis >= 0 && !(cost < best.cost)) continue;
    best = {axis, plane_[axis][k], cost, acc, right_box[k], count, right_count[k]};
  }
}

SpatialSplit SpatialBins::best_split(std::span<const PrimRef> refs,
                                     const std::vector<Triangle>& tris, const Box4& bounds,
                                     int bins, const BvhConfig& config, TaskPool* pool) {
  bins_ = bins;
  const Aabb box = bounds.aabb();
  bool valid[3];
  auto bin_axis = [&](std::size_t a, int) {
    const int axis = static_cast<int>(a);
    valid[axis] = set_planes(axis, box.lo[axis], box.hi[axis]);
    if (!valid[axis]) return;
    for (int k = 0; k < bins_; ++k) {
      box_[axis][k] = Aabb{};
      enter_[axis][k] = exit_[axis][k] = 0;
    }
    for (const PrimRef& r : refs) bin(r, tris[r.id()], axis);
  };
  if (pool)
    pool->parallel_for(3, bin_axis);
  else
    for (int axis = 0; axis < 3; ++axis) bin_axis(static_cast<std::size_t>(axis), 0);
  SpatialSplit best;
  for (int axis = 0; axis < 3; ++axis)
    if (valid[axis]) sweep(axis, box.area(), config, best);
  return best;
}

std::uint64_t split_references(std::span<const PrimRef> refs, const std::vector<Triangle>& tris,
                               const SpatialSplit& split, bool unsplit,
                               std::uint64_t max_duplicates, std::vector<PrimRef>& left,
                               std::vector<PrimRef>& right) {
  const int a = split.axis;
  const float p = split.position;
  const float area_l = split.left.area(), area_r = split.right.area();
  const auto n_l = static_cast<float>(split.left_count), n_r = static_cast<float>(split.right_count);
  std::uint64_t duplicates = 0;
  for (const PrimRef& r : refs) {
    if (r.lo[a] >= p) {
      right.push_back(r);
      continue;
    }
    if (r.hi[a] <= p) {
      left.push_back(r);
      continue;
    }
    const ChoppedBoxes c = chop_reference(r, tris[r.id()], a, p);
    const bool has_l = !c.below.empty(), has_r = !c.above.empty();
    if (has_l && has_r) {  // unsplitting: Stich et al. 2009, section 4.4
      const Aabb whole = ref_box(r);
      const float cost_split = area_l * n_l + area_r * n_r;
      const float cost_left = united(split.left, whole).area() * n_l + area_r * (n_r - 1.0f);
      const float cost_right = area_l * (n_l - 1.0f) + united(split.right, whole).area() * n_r;
      const bool whole_only = duplicates >= max_duplicates;
      if (whole_only || (unsplit && std::min(cost_left, cost_right) < cost_split)) {
        (cost_left <= cost_right ? left : right).push_back(r);
        continue;
      }
      ++duplicates;
    }
    if (has_l) left.push_back(make_ref(c.below, r.id()));
    if (has_r) right.push_back(make_ref(c.above, r.id()));
  }
  return duplicates;
}

}  // namespace hrpp::bvh_build
