#include "bvh/binned_sah_builder.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <span>

#include "bvh/prim_refs.h"
#include "bvh/ref_partition.h"
#include "bvh/sah_bins.h"
#include "bvh/sbvh_builder.h"
#include "bvh/small_node.h"
#include "bvh/subtrees.h"
#include "common/task_pool.h"
#include "common/error.h"

namespace hrpp {
namespace {

using bvh_build::BinMap;
using bvh_build::Box4;
using bvh_build::PrimRef;
using bvh_build::RefPartitioner;
using bvh_build::References;
using bvh_build::SahBins;
using bvh_build::Split;

// References per task when binning in parallel.
constexpr std::uint32_t kBinChunk = 1u << 14;
// Nodes with at least this many references are binned into two sets of bins (SahBins::add).
constexpr std::uint32_t kDualBinsMin = 64;

struct NodeTask {
  std::uint32_t begin = 0, end = 0;
  int depth = 0;
  Box4 bounds;
  bool has_centroids = false;  // centroids known (else split() computes them)
  Box4 centroids;
  std::uint32_t count() const { return end - begin; }
};

// What each thread keeps between nodes.
struct Scratch {
  SahBins bins, odd_bins;
  Box4 centroids;
  RefPartitioner partitioner;
  bvh_build::SmallNode small;
};

// A node of the top of the tree (split by all threads) or the root of a subtree (subtree >= 0).
struct TopNode {
  Bvh::Node node;
  int subtree = -1;
};

class Builder {
 public:
  Builder(const BvhConfig& config, References& refs, TaskPool& pool)
      : config_(config), refs_(refs.refs.get(), refs.count), pool_(pool), scratch_(pool.size()) {
    root_.end = static_cast<std::uint32_t>(refs_.size());
    root_.bounds = refs.bounds;
    root_.has_centroids = true;
    root_.centroids = refs.centroids;
    bins_ = std::clamp(config.bin_count, 2, bvh_build::kMaxBins);
  }

  Bvh run() {
    build_top();
    locals_.resize(subtrees_.size());
    pool_.parallel_for(subtrees_.size(), [&](std::size_t k, int thread) {
      const std::size_t s = subtree_order_[k];
      locals_[s].reserve(2 * std::size_t{std::max(1u, subtrees_[s].count())} - 1);
      locals_[s].emplace_back();
      build_subtree(subtrees_[s], 0, locals_[s], scratch_[thread]);
    });
    Bvh bvh;
    stitch(bvh.nodes);
    bvh.prim_ids.resize(refs_.size());
    for (std::size_t i = 0; i < refs_.size(); ++i) bvh.prim_ids[i] = refs_[i].id();
    return bvh;
  }

 private:
  Split sah_split(const NodeTask& t, const Box4& centroids, const BinMap& map, Scratch& s,
                  bool parallel);
  Box4 centroid_bounds(const NodeTask& t, bool parallel);
  bool split(const NodeTask& t, NodeTask& left, NodeTask& right, Scratch& s, bool parallel);
  void bin(const NodeTask& t, const BinMap& map, Scratch& s, bool parallel);
  void median_split(const NodeTask& t, const Box4& centroids, NodeTask& left, NodeTask& right);
  void build_top();
  void build_subtree(const NodeTask& t, std::uint32_t index, std::vector<Bvh::Node>& out,
                     Scratch& s);
  void stitch(std::vector<Bvh::Node>& nodes);
  std::uint32_t place(std::uint32_t top, std::uint32_t final_index, std::uint32_t cursor);

  const BvhConfig& config_;
  std::span<PrimRef> refs_;
  TaskPool& pool_;
  std::vector<Scratch> scratch_;  // one per pool thread
  int bins_ = 16;
  NodeTask root_;
  std::vector<TopNode> top_;
  std::vector<NodeTask> subtrees_;
  std::vector<std::size_t> subtree_order_;   // largest first
  std::vector<std::vector<Bvh::Node>> locals_;  // subtree k's nodes, its root first
  std::vector<std::uint32_t> top_final_;      // final index of each top node
  std::vector<std::pair<std::uint32_t, std::uint32_t>> subtree_place_;  // root index, base
};

// The SAH split of t (axis -1: none, or t is deep enough for object medians only), by the path
// for its size: two references, a small node, or bins (parallel: on the whole pool).
Split Builder::sah_split(const NodeTask& t, const Box4& centroids, const BinMap& map, Scratch& s,
                         bool parallel) {
  const float area = t.bounds.area();
  if (t.depth >= bvh_build::kMedianSplitDepth) return {};
  if (t.count() == 2) return bvh_build::split_pair(refs_.data() + t.begin, centroids, area, config_);
  if (t.count() <= bvh_build::kMaxSmallNode) {
    s.small.load(refs_.data() + t.begin, t.count(), map);
    return s.small.best_split(centroids, area, config_);
  }
  bin(t, map, s, parallel);
  return bvh_build::best_split(s.bins, map, centroids, area, config_);
}

// Bounds of t's centroids (in parallel: per-thread bounds over chunks, merged).
Box4 Builder::centroid_bounds(const NodeTask& t, bool parallel) {
  auto grow = [&](std::uint32_t begin, std::uint32_t end, Box4& b) {
    for (std::uint32_t i = begin; i < end; ++i) b.grow(refs_[i].centroid());
  };
  Box4 all;
  if (!parallel || t.count() <= kBinChunk) {
    grow(t.begin, t.end, all);
    return all;
  }
  for (Scratch& x : scratch_) x.centroids = Box4{};
  pool_.parallel_for(chunks(t.count(), kBinChunk), [&](std::size_t k, int thread) {
    const std::uint32_t b = t.begin + static_cast<std::uint32_t>(k) * kBinChunk;
    grow(b, std::min(b + kBinChunk, t.end), scratch_[thread].centroids);
  });
  for (const Scratch& x : scratch_) all.grow(x.centroids);
  return all;
}

// Splits node t into two children, or returns false when t is a leaf. With `parallel`, binning
// and partition run on the whole pool. Either way the outcome depends on t's references only.
bool Builder::split(const NodeTask& t, NodeTask& left, NodeTask& right, Scratch& s,
                    bool parallel) {
  const std::uint32_t count = t.count();
  if (count <= 1) return false;
  const bool may_be_leaf = t.depth > 0 && count <= static_cast<std::uint32_t>(config_.max_leaf_size);
  const Box4 centroids = t.has_centroids ? t.centroids : centroid_bounds(t, parallel);
  const BinMap map(centroids, bins_);
  const Split sah = sah_split(t, centroids, map, s, parallel);
  if (sah.axis < 0) {  // no plane separates the centroids (or we are deep): object median
    if (may_be_leaf) return false;
    median_split(t, centroids, left, right);
    return true;
  }
  if (may_be_leaf && config_.intersection_cost * static_cast<float>(count) <= sah.cost)
    return false;
  std::uint32_t mid = t.begin + 1;  // split_pair put the left reference first
  if (count > 2 && count <= bvh_build::kMaxSmallNode)
    mid = t.begin + s.small.partition(refs_.data() + t.begin, sah);
  else if (count > bvh_build::kMaxSmallNode)
    mid = s.partitioner.run(refs_.data(), t.begin, t.end, {&map, sah.axis, sah.bin},
                            parallel ? &pool_ : nullptr);
  left = {t.begin, mid, t.depth + 1, sah.left, sah.has_centroids, sah.left_centroids};
  right = {mid, t.end, t.depth + 1, sah.right, sah.has_centroids, sah.right_centroids};
  return true;
}

// Bins t's references into s.bins; in parallel, each thread bins whole chunks into its own
// scratch bins, merged into s.bins after (min, max and sums: the same bins in any order).
void Builder::bin(const NodeTask& t, const BinMap& map, Scratch& s, bool parallel) {
  if (!parallel || t.count() <= kBinChunk) {
    s.bins.clear(bins_);
    if (t.count() >= kDualBinsMin)
      s.bins.add(refs_.data() + t.begin, t.count(), map, s.odd_bins);
    else
      s.bins.add(refs_.data() + t.begin, t.count(), map);
    return;
  }
  for (Scratch& x : scratch_) x.bins.clear(bins_);
  pool_.parallel_for(chunks(t.count(), kBinChunk), [&](std::size_t k, int thread) {
    const std::uint32_t b = t.begin + static_cast<std::uint32_t>(k) * kBinChunk;
    Scratch& x = scratch_[thread];
    x.bins.add(refs_.data() + b, std::min(kBinChunk, t.end - b), map, x.odd_bins);
  });
  for (Scratch& x : scratch_)
    if (&x != &s) s.bins.merge(x.bins, bins_);
}

// Object median (bvh_build::median_partition), with the halves' bounds.
void Builder::median_split(const NodeTask& t, const Box4& centroids, NodeTask& left,
                           NodeTask& right) {
  const std::uint32_t mid =
      t.begin + bvh_build::median_partition(refs_.data() + t.begin, t.count(), centroids);
  left = {t.begin, mid, t.depth + 1, {}, true, {}};
  right = {mid, t.end, t.depth + 1, {}, true, {}};
  for (NodeTask* c : {&left, &right})
    for (std::uint32_t i = c->begin; i < c->end; ++i) {
      c->bounds.grow(Box4{refs_[i].lo4(), refs_[i].hi4()});
      c->centroids.grow(refs_[i].centroid());
    }
}

// Splits the top of the tree breadth first with all threads until the nodes are small enough to
// be subtrees; the threshold only changes who does the work, not the tree.
void Builder::build_top() {
  const std::size_t threshold = bvh_build::subtree_threshold(refs_.size(), pool_.size());
  std::vector<std::pair<NodeTask, std::uint32_t>> queue{{root_, 0}};  // task, top node
  top_.resize(1);
  for (std::size_t i = 0; i < queue.size(); ++i) {
    const auto [t, ti] = queue[i];
    top_[ti].node.bounds = t.bounds.aabb();
    if (t.count() <= threshold) {
      top_[ti].subtree = static_cast<int>(subtrees_.size());
      subtrees_.push_back(t);
      continue;
    }
    NodeTask l, r;
    if (!split(t, l, r, scratch_[0], true)) {
      top_[ti].node.first = t.begin;
      top_[ti].node.count = t.count();
      continue;
    }
    const auto pair = static_cast<std::uint32_t>(top_.size());
    top_[ti].node.first = pair;
    top_.resize(top_.size() + 2);
    queue.push_back({l, pair});
    queue.push_back({r, pair + 1});
  }
  subtree_order_.resize(subtrees_.size());
  for (std::size_t k = 0; k < subtrees_.size(); ++k) subtree_order_[k] = k;
  std::stable_sort(subtree_order_.begin(), subtree_order_.end(), [&](std::size_t x, std::size_t y) {
    return subtrees_[x].count() > subtrees_[y].count();
  });
}

// Depth first on one thread; children pairs numbered in visiting order, as a sequential build.
void Builder::build_subtree(const NodeTask& t, std::uint32_t index, std::vector<Bvh::Node>& out,
                            Scratch& s) {
  out[index].bounds = t.bounds.aabb();
  NodeTask l, r;
  if (!split(t, l, r, s, false)) {
    out[index].first = t.begin;
    out[index].count = t.count();
    return;
  }
  const auto pair = static_cast<std::uint32_t>(out.size());
  out[index].first = pair;
  out.resize(out.size() + 2);  // within the reserved 2 count - 1: no reallocation
  build_subtree(l, pair, out, s);
  build_subtree(r, pair + 1, out, s);
}

// Gives top node `top` the index final_index and numbers the nodes under it depth first from
// `cursor`, as one thread building the whole tree would; returns the next free index.
std::uint32_t Builder::place(std::uint32_t top, std::uint32_t final_index, std::uint32_t cursor) {
  top_final_[top] = final_index;
  const TopNode& n = top_[top];
  if (n.subtree >= 0) {
    subtree_place_[n.subtree] = {final_index, cursor};
    return cursor + static_cast<std::uint32_t>(locals_[n.subtree].size()) - 1;
  }
  if (n.node.is_leaf()) return cursor;
  cursor = place(n.node.first, cursor, cursor + 2);
  return place(n.node.first + 1, top_final_[n.node.first] + 1, cursor);
}

// Numbers every node (place), then writes the top nodes and copies the subtrees.
void Builder::stitch(std::vector<Bvh::Node>& nodes) {
  top_final_.resize(top_.size());
  subtree_place_.resize(subtrees_.size());
  nodes.resize(place(0, 0, 1));
  for (std::size_t i = 0; i < top_.size(); ++i) {
    if (top_[i].subtree >= 0) continue;
    Bvh::Node n = top_[i].node;
    if (!n.is_leaf() && top_.size() > 1) n.first = top_final_[n.first];
    nodes[top_final_[i]] = n;
  }
  for (std::size_t k = 0; k < subtrees_.size(); ++k) {  // memory-bound: one thread is enough
    const auto [root, base] = subtree_place_[k];
    bvh_build::copy_subtree(locals_[k], root, base, 0, nodes);  // leaves index refs_ already
  }
}

}  // namespace

Bvh build_bvh(const Scene& scene, const BvhConfig& config) {
  if (config.bin_count < 2 || config.bin_count > bvh_build::kMaxBins)
    throw Error("--bvh-bins: must be between 2 and " + std::to_string(bvh_build::kMaxBins));
  if (config.max_leaf_size < 1 || config.max_leaf_size > 255)
    throw Error("--bvh-max-leaf: must be between 1 and 255");
  if (!(config.intersection_cost > 0.0f && config.intersection_cost <= 1e6f))
    throw Error("--bvh-intersection-cost: must be above 0 and at most 1e6");
  if (!(config.traversal_cost > 0.0f && config.traversal_cost <= 1e6f))
    throw Error("BvhConfig::traversal_cost: must be above 0 and at most 1e6");
  if (config.threads < 0) throw Error("--threads: must be 0 (all) or more");
  if (!(config.duplicate_budget >= 0.0f) || !(config.spatial_alpha >= 0.0f))
    throw Error("--bvh-splits spatial: the duplicate budget and alpha must be 0 or more");

  const auto start = std::chrono::steady_clock::now();
  TaskPool pool(resolve_threads(config.threads));
  References refs = bvh_build::make_references(scene, pool);
  Bvh bvh = config.splits == BvhSplits::kSpatial ? build_sbvh(scene, config, refs, pool)
                                                 : Builder(config, refs, pool).run();
  bvh.degenerate_count = refs.degenerate;
  bvh.build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return bvh;
}

}  // namespace hrpp
