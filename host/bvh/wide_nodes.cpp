#include "bvh/wide_nodes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "bvh/aabb.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "wide_node.h"

namespace hrpp {
namespace {

using gpu::hrpp_grid_bound;

constexpr float kSmallestNormal = 0x1p-126f;
constexpr std::uint32_t kTopCoordinate = 255;

// A child of a wide node: its box and reference (binary node index, or ~leaf).
struct Child {
  Aabb box;
  int ref = 0;
};

Child binary_child(const gpu::BvhNode& n, bool right) {
  const glm::vec4& xy = right ? n.right_xy : n.left_xy;
  Child c;
  c.box.lo = {xy.x, xy.z, right ? n.lr_z.z : n.lr_z.x};
  c.box.hi = {xy.y, xy.w, right ? n.lr_z.w : n.lr_z.y};
  c.ref = right ? n.link.y : n.link.x;
  return c;
}

// x as a device that flushes subnormal results to zero computes it.
float flushed(float x) { return std::fpclassify(x) == FP_SUBNORMAL ? std::copysign(0.0f, x) : x; }
bool at_or_below(float x, float bound) { return x <= bound && flushed(x) <= bound; }
bool at_or_above(float x, float bound) { return x >= bound && flushed(x) >= bound; }

// One axis of a node's grid: its origin (the box's low bound, moved down to a normal float or
// zero) and the smallest step whose 255 steps reach the box's high bound.
struct Grid {
  float origin = 0.0f;
  std::uint32_t exponent = HRPP_WIDE_EXPONENT_MIN;

  Grid(float lo, float hi) {
    origin = std::fpclassify(lo) != FP_SUBNORMAL ? lo : (lo < 0.0f ? -kSmallestNormal : 0.0f);
    const double span = static_cast<double>(hi) - origin;
    if (span > 0.0) {  // start a step below the estimate: the loop finds the exact one
      const int guess = std::ilogb(span / kTopCoordinate) - 1 + 127;
      exponent = static_cast<std::uint32_t>(
          std::clamp<int>(guess, HRPP_WIDE_EXPONENT_MIN, HRPP_WIDE_EXPONENT_MAX));
    }
    while (!reaches(hi)) {
      if (++exponent > HRPP_WIDE_EXPONENT_MAX)
        throw Error("--bvh-nodes wide4: a BVH node spans [" + std::to_string(lo) + ", " +
                    std::to_string(hi) + "], too wide for its 8-bit grid");
    }
  }

  bool reaches(float hi) const {
    const float top = bound(kTopCoordinate);
    return std::isfinite(top) && at_or_above(top, hi);
  }
  float bound(std::uint32_t q) const { return hrpp_grid_bound(origin, step(), q); }

  // The largest coordinate whose bound is at or below `lo` (0 always is: origin <= lo).
  std::uint32_t below(float lo) const {
    std::uint32_t q = estimate(std::floor((static_cast<double>(lo) - origin) / step()));
    while (q > 0 && !at_or_below(bound(q), lo)) --q;
    while (q < kTopCoordinate && at_or_below(bound(q + 1), lo)) ++q;
    return q;
  }
  // The smallest coordinate whose bound is at or above `hi` (255 always is: reaches()).
  std::uint32_t above(float hi) const {
    std::uint32_t q = estimate(std::ceil((static_cast<double>(hi) - origin) / step()));
    while (q < kTopCoordinate && !at_or_above(bound(q), hi)) ++q;
    while (q > 0 && at_or_above(bound(q - 1), hi)) --q;
    return q;
  }

 private:
  // The kernels' decoding of a step: the exponent as axis 0 of a packed word.
  float step() const { return gpu::hrpp_grid_step(exponent, 0u); }
  static std::uint32_t estimate(double q) {
    return static_cast<std::uint32_t>(std::clamp(q, 0.0, static_cast<double>(kTopCoordinate)));
  }
};

// The wide tree: per wide node (depth-first, the root first) its children, whose references
// are wide node indices or ~leaf.
using WideTree = std::vector<std::vector<Child>>;

class Collapser {
 public:
  explicit Collapser(const GpuBvh& bvh) : bvh_(bvh) {}

  // Places the wide node standing for binary node `node`; returns its index. No depth check:
  // every wide level takes at least one binary level, and make_gpu_layout checked those.
  int place(int node) {
    std::vector<Child> children = open(node);
    const int self = static_cast<int>(out_.size());
    out_.emplace_back();
    for (Child& c : children)
      if (!is_leaf_ref(c.ref)) c.ref = place(c.ref);
    out_[self] = std::move(children);
    return self;
  }

  WideTree take() { return std::move(out_); }

 private:
  // Binary node `node`'s two children, the largest interior one opened until there are four;
  // children with an empty box are dropped.
  std::vector<Child> open(int node) const {
    std::vector<Child> c = {binary_child(bvh_.nodes[node], false),
                            binary_child(bvh_.nodes[node], true)};
    while (c.size() < HRPP_WIDE_CHILDREN) {
      auto largest = c.end();
      for (auto it = c.begin(); it != c.end(); ++it)
        if (!is_leaf_ref(it->ref) && (largest == c.end() || it->box.area() > largest->box.area()))
          largest = it;
      if (largest == c.end()) break;
      const gpu::BvhNode& n = bvh_.nodes[largest->ref];
      *largest = binary_child(n, false);
      c.insert(largest + 1, binary_child(n, true));
    }
    std::erase_if(c, [](const Child& x) { return x.box.empty(); });
    return c;
  }

  const GpuBvh& bvh_;
  WideTree out_;
};

WideTree collapse(const GpuBvh& bvh) {
  if (bvh.nodes.empty()) throw Error("BVH has no nodes");
  Collapser c(bvh);
  c.place(0);
  return c.take();
}

gpu::WideNode quantised(const std::vector<Child>& children) {
  Aabb box;
  for (const Child& c : children) box.grow(c.box);
  if (children.empty()) box = Aabb{glm::vec3(0.0f), glm::vec3(0.0f)};
  gpu::WideNode w{};
  w.child = glm::ivec4(HRPP_WIDE_EMPTY_SLOT);
  for (int axis = 0; axis < 3; ++axis) {
    const Grid g(box.lo[axis], box.hi[axis]);
    w.origin[axis] = g.origin;
    w.exponents |= g.exponent << (8 * axis);
    for (std::size_t i = 0; i < children.size(); ++i) {
      w.lo[axis] |= g.below(children[i].box.lo[axis]) << (8 * i);
      w.hi[axis] |= g.above(children[i].box.hi[axis]) << (8 * i);
    }
  }
  for (std::size_t i = 0; i < children.size(); ++i) w.child[static_cast<int>(i)] = children[i].ref;
  return w;
}

gpu::WideFloatNode exact(const std::vector<Child>& children) {
  gpu::WideFloatNode w{};
  w.child = glm::ivec4(HRPP_WIDE_EMPTY_SLOT);
  for (std::size_t k = 0; k < children.size(); ++k) {
    const int i = static_cast<int>(k);
    const Aabb& b = children[k].box;
    w.lo_x[i] = b.lo.x;
    w.hi_x[i] = b.hi.x;
    w.lo_y[i] = b.lo.y;
    w.hi_y[i] = b.hi.y;
    w.lo_z[i] = b.lo.z;
    w.hi_z[i] = b.hi.z;
    w.child[i] = children[k].ref;
  }
  return w;
}

}  // namespace

std::vector<gpu::WideNode> make_wide_nodes(const GpuBvh& bvh) {
  const WideTree tree = collapse(bvh);
  std::vector<gpu::WideNode> out;
  out.reserve(tree.size());
  for (const std::vector<Child>& children : tree) out.push_back(quantised(children));
  return out;
}

std::vector<gpu::WideFloatNode> make_wide_float_nodes(const GpuBvh& bvh) {
  const WideTree tree = collapse(bvh);
  std::vector<gpu::WideFloatNode> out;
  out.reserve(tree.size());
  for (const std::vector<Child>& children : tree) out.push_back(exact(children));
  return out;
}

}  // namespace hrpp
