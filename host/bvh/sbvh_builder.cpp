#include "bvh/sbvh_builder.h"

#include <algorithm>
#include <span>
#include <vector>

#include "bvh/ref_partition.h"
#include "bvh/sah_bins.h"
#include "bvh/spatial_split.h"
#include "bvh/subtrees.h"

namespace hrpp {
namespace {

using bvh_build::Box4;
using bvh_build::PrimRef;

struct Task {
  std::vector<PrimRef> refs;
  Box4 bounds;
  int depth = 0;
  std::uint64_t budget = 0;  // duplicates this subtree may still make
};

struct Scratch {
  bvh_build::SahBins bins, odd_bins;
  bvh_build::SpatialBins spatial;
  bvh_build::RefPartitioner partitioner;
};

// Nodes and leaf ids of one part of the tree (the top, or one subtree), numbered locally.
struct Part {
  std::vector<Bvh::Node> nodes;
  std::vector<std::uint32_t> ids;
};

Box4 centroid_bounds(std::span<const PrimRef> refs) {
  Box4 b;
  for (const PrimRef& r : refs) b.grow(r.centroid());
  return b;
}

Box4 bounds_of(std::span<const PrimRef> refs) {
  Box4 b;
  for (const PrimRef& r : refs) b.grow(Box4{r.lo4(), r.hi4()});
  return b;
}

float overlap_area(const Box4& a, const Box4& b) {
  Box4 c{simd::max(a.lo, b.lo), simd::min(a.hi, b.hi)};
  const Aabb box = c.aabb();
  return box.area();  // 0 when empty
}

// The whole tree: the top's nodes first, then each subtree's (its root in the top node it
// replaces), the top's leaf ids first, then each subtree's.
Bvh stitch(Part& top, std::vector<Part>& parts, const std::vector<std::uint32_t>& roots) {
  Bvh bvh;
  bvh.nodes = std::move(top.nodes);
  bvh.prim_ids = std::move(top.ids);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const std::vector<Bvh::Node>& local = parts[k].nodes;
    const auto base = static_cast<std::uint32_t>(bvh.nodes.size());
    const auto id_base = static_cast<std::uint32_t>(bvh.prim_ids.size());
    bvh.nodes.resize(bvh.nodes.size() + local.size() - 1);
    bvh_build::copy_subtree(local, roots[k], base, id_base, bvh.nodes);
    bvh.prim_ids.insert(bvh.prim_ids.end(), parts[k].ids.begin(), parts[k].ids.end());
  }
  return bvh;
}

class SbvhBuilder {
 public:
  SbvhBuilder(const Scene& scene, const BvhConfig& config, TaskPool& pool)
      : tris_(scene.triangles), config_(config), pool_(pool), scratch_(pool.size()) {}

  Bvh run(Task root);

 private:
  struct Subtree {
    Task task;
    std::uint32_t root;  // its top node
  };
  std::vector<Subtree> build_top(Task root, std::size_t threshold, Part& top);
  bool split(Task& t, Task& left, Task& right, Scratch& s, bool parallel = false) const;
  bool split_spatially(Task& t, const bvh_build::SpatialSplit& sp, Task& left, Task& right) const;
  void split_by_objects(Task& t, std::uint32_t mid, Task& left, Task& right) const;
  void build(Task t, std::uint32_t index, Part& out, Scratch& s) const;
  static void finish(const Task& parent, std::uint64_t duplicates, Task& left, Task& right);

  const std::vector<Triangle>& tris_;
  const BvhConfig& config_;
  TaskPool& pool_;
  std::vector<Scratch> scratch_;
  float alpha_area_ = 0.0f;
};

// The children's bounds, depth and budgets: what is left of the parent's budget after the
// split's duplicates, shared in proportion to the children's references.
void SbvhBuilder::finish(const Task& parent, std::uint64_t duplicates, Task& left, Task& right) {
  const std::uint64_t rest = parent.budget - std::min(parent.budget, duplicates);
  const std::uint64_t nl = left.refs.size(), nr = right.refs.size();
  left.budget = rest * nl / (nl + nr);
  right.budget = rest - left.budget;
  for (Task* c : {&left, &right}) {
    c->bounds = bounds_of(c->refs);
    c->depth = parent.depth + 1;
  }
}

// Parent references [0, mid) left, [mid, n) right.
void SbvhBuilder::split_by_objects(Task& t, std::uint32_t mid, Task& left, Task& right) const {
  left.refs.assign(t.refs.begin(), t.refs.begin() + mid);
  right.refs.assign(t.refs.begin() + mid, t.refs.end());
  finish(t, 0, left, right);
}

// At most t.budget duplicates (split_references). False when a side would be empty.
bool SbvhBuilder::split_spatially(Task& t, const bvh_build::SpatialSplit& sp, Task& left,
                                  Task& right) const {
  left.refs.clear();
  right.refs.clear();
  const std::uint64_t duplicates = bvh_build::split_references(
      t.refs, tris_, sp, config_.unsplit, t.budget, left.refs, right.refs);
  if (left.refs.empty() || right.refs.empty()) return false;
  finish(t, duplicates, left, right);
  return true;
}

// Splits t into two children, or returns false when t is a leaf. With `parallel`, the spatial
// bins' axes are binned on the pool.
bool SbvhBuilder::split(Task& t, Task& left, Task& right, Scratch& s, bool parallel) const {
  const auto count = static_cast<std::uint32_t>(t.refs.size());
  if (count <= 1) return false;
  const bool may_be_leaf =
      t.depth > 0 && count <= static_cast<std::uint32_t>(config_.max_leaf_size);
  const Box4 centroids = centroid_bounds(t.refs);
  const int bins = std::clamp(config_.bin_count, 2, bvh_build::kMaxBins);
  const bvh_build::BinMap map(centroids, bins);
  const float area = t.bounds.area();
  bvh_build::Split object;
  if (t.depth < bvh_build::kMedianSplitDepth) {
    s.bins.clear(bins);
    s.bins.add(t.refs.data(), count, map, s.odd_bins);
    object = bvh_build::best_split(s.bins, map, centroids, area, config_);
  }
  bvh_build::SpatialSplit spatial;
  if (t.budget > 0 &&
      t.depth < bvh_build::kMedianSplitDepth &&
      (object.axis < 0 || overlap_area(object.left, object.right) > alpha_area_)) {
    spatial = s.spatial.best_split(t.refs, tris_, t.bounds, bins, config_,
                                   parallel ? &pool_ : nullptr);
    if (object.axis >= 0 && !(spatial.cost < object.cost)) spatial.axis = -1;
  }
  const float best = spatial.axis >= 0 ? spatial.cost : object.cost;
  if (may_be_leaf && ((object.axis < 0 && spatial.axis < 0) ||
                      config_.intersection_cost * static_cast<float>(count) <= best))
    return false;
  if (spatial.axis >= 0 && split_spatially(t, spatial, left, right)) return true;
  std::uint32_t mid = 0;
  if (object.axis >= 0)
    mid = s.partitioner.run(t.refs.data(), 0, count, {&map, object.axis, object.bin});
  else
    mid = bvh_build::median_partition(t.refs.data(), count, centroids);
  split_by_objects(t, mid, left, right);
  return true;
}

// Builds t's subtree into out: t at out.nodes[index], children pairs appended depth first.
void SbvhBuilder::build(Task t, std::uint32_t index, Part& out, Scratch& s) const {
  out.nodes[index].bounds = t.bounds.aabb();
  Task l, r;
  if (!split(t, l, r, s)) {
    out.nodes[index].first = static_cast<std::uint32_t>(out.ids.size());
    out.nodes[index].count = static_cast<std::uint32_t>(t.refs.size());
    for (const PrimRef& ref : t.refs) out.ids.push_back(ref.id());
    return;
  }
  t.refs = {};  // the children hold the references now
  const auto pair = static_cast<std::uint32_t>(out.nodes.size());
  out.nodes[index].first = pair;
  out.nodes.resize(out.nodes.size() + 2);
  build(std::move(l), pair, out, s);
  build(std::move(r), pair + 1, out, s);
}

// The top of the tree, level by level: the nodes over `threshold` references of a level are
// split together (on the pool's threads; a lone node bins its spatial axes on them), the rest
// become subtrees; top nodes are numbered breadth first.
std::vector<SbvhBuilder::Subtree> SbvhBuilder::build_top(Task root, std::size_t threshold,
                                                         Part& top) {
  top.nodes.resize(1);
  std::vector<Subtree> subtrees;
  std::vector<Subtree> level;
  level.push_back({std::move(root), 0});
  while (!level.empty()) {
    std::vector<Task> lefts(level.size()), rights(level.size());
    std::vector<char> did_split(level.size(), 0);
    auto work = [&](std::size_t k, int thread) {
      Task& t = level[k].task;
      if (t.refs.size() > threshold)
        did_split[k] = split(t, lefts[k], rights[k], scratch_[thread], level.size() == 1);
    };
    if (level.size() == 1)
      work(0, 0);
    else
      pool_.parallel_for(level.size(), work);
    std::vector<Subtree> next;
    for (std::size_t k = 0; k < level.size(); ++k) {
      Task& t = level[k].task;
      const std::uint32_t index = level[k].root;
      if (t.refs.size() <= threshold) {
        subtrees.push_back(std::move(level[k]));
        continue;
      }
      Bvh::Node& node = top.nodes[index];
      node.bounds = t.bounds.aabb();
      if (!did_split[k]) {
        node.first = static_cast<std::uint32_t>(top.ids.size());
        node.count = static_cast<std::uint32_t>(t.refs.size());
        for (const PrimRef& ref : t.refs) top.ids.push_back(ref.id());
        continue;
      }
      const auto pair = static_cast<std::uint32_t>(top.nodes.size());
      node.first = pair;
      top.nodes.resize(top.nodes.size() + 2);
      next.push_back({std::move(lefts[k]), pair});
      next.push_back({std::move(rights[k]), pair + 1});
    }
    level = std::move(next);
  }
  return subtrees;
}

Bvh SbvhBuilder::run(Task root) {
  alpha_area_ = config_.spatial_alpha * root.bounds.area();
  const std::size_t threshold = bvh_build::subtree_threshold(root.refs.size(), pool_.size());
  Part top;
  std::vector<Subtree> subtrees = build_top(std::move(root), threshold, top);
  std::stable_sort(subtrees.begin(), subtrees.end(), [](const Subtree& x, const Subtree& y) {
    return x.task.refs.size() > y.task.refs.size();
  });
  std::vector<Part> parts(subtrees.size());
  std::vector<std::uint32_t> roots(subtrees.size());
  for (std::size_t k = 0; k < subtrees.size(); ++k) roots[k] = subtrees[k].root;
  pool_.parallel_for(subtrees.size(), [&](std::size_t k, int thread) {
    parts[k].nodes.resize(1);
    build(std::move(subtrees[k].task), 0, parts[k], scratch_[thread]);
  });
  return stitch(top, parts, roots);
}

}  // namespace

Bvh build_sbvh(const Scene& scene, const BvhConfig& config, bvh_build::References& refs,
               TaskPool& pool) {
  Task root;
  root.refs.assign(refs.refs.get(), refs.refs.get() + refs.count);
  refs.refs.reset();
  root.bounds = refs.bounds;
  root.budget = static_cast<std::uint64_t>(
      std::max(0.0, static_cast<double>(config.duplicate_budget) * refs.count));
  return SbvhBuilder(scene, config, pool).run(std::move(root));
}

}  // namespace hrpp
