#include "bvh/binned_sah_builder.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <thread>

#include "common/error.h"
#include "scene/load_scene.h"

namespace hrpp {
namespace {

constexpr int kMaxBins = 64;
// Below this depth the builder splits by SAH; from it on by object median, which bounds the
// tree depth (and so the traversal stack, HRPP_STACK_SIZE) by this + log2(triangles).
constexpr int kMedianSplitDepth = 36;
// Subtrees at least this big are built on another thread while one is free.
constexpr std::uint32_t kParallelMinPrims = 16384;

struct PrimRef {
  Aabb box;
  glm::vec3 centroid;
  std::uint32_t id;
};

struct Split {
  int axis = -1;     // -1: no SAH split found
  int bin = 0;       // left side takes bins [0, bin]
  float cost = 0.0f;
};

class Builder {
 public:
  Builder(const BvhConfig& config, std::vector<PrimRef> refs)
      : config_(config), refs_(std::move(refs)) {
    nodes_.resize(std::max<std::size_t>(1, 2 * refs_.size()));
    const int threads = config.threads > 0 ? config.threads
                                           : static_cast<int>(std::thread::hardware_concurrency());
    free_threads_ = std::max(0, threads - 1);
  }

  Bvh run() {
    node_count_ = 1;
    build(0, 0, static_cast<std::uint32_t>(refs_.size()), 0);
    Bvh bvh;
    nodes_.resize(node_count_);
    bvh.nodes = std::move(nodes_);
    bvh.prim_ids.reserve(refs_.size());
    for (const PrimRef& r : refs_) bvh.prim_ids.push_back(r.id);
    return bvh;
  }

 private:
  void build(std::uint32_t node_index, std::uint32_t begin, std::uint32_t end, int depth) {
    Aabb bounds, centroids;
    for (std::uint32_t i = begin; i < end; ++i) {
      bounds.grow(refs_[i].box);
      centroids.grow(refs_[i].centroid);
    }
    Bvh::Node& node = nodes_[node_index];
    node.bounds = bounds;
    const std::uint32_t count = end - begin;
    const bool root = depth == 0;

    if (count <= 1) return make_leaf(node, begin, count);

    std::uint32_t mid = begin;
    const Split split = depth < kMedianSplitDepth ? find_sah_split(begin, end, bounds, centroids)
                                                  : Split{};
    const float leaf_cost = config_.intersection_cost * static_cast<float>(count);
    if (split.axis >= 0) {
      if (!root && count <= static_cast<std::uint32_t>(config_.max_leaf_size) &&
          leaf_cost <= split.cost)
        return make_leaf(node, begin, count);
      mid = partition(begin, end, centroids, split);
    }
    if (mid == begin || mid == end) {
      // No SAH plane separates the centroids (or we are deep): object median on the widest axis.
      if (!root && count <= static_cast<std::uint32_t>(config_.max_leaf_size))
        return make_leaf(node, begin, count);
      mid = median_split(begin, end, centroids);
    }

    const std::uint32_t left = node_count_.fetch_add(2);
    node.first = left;
    node.count = 0;
    if (count >= kParallelMinPrims && take_thread()) {
      std::thread worker([=, this] { build(left, begin, mid, depth + 1); });
      build(left + 1, mid, end, depth + 1);
      worker.join();
      ++free_threads_;
    } else {
      build(left, begin, mid, depth + 1);
      build(left + 1, mid, end, depth + 1);
    }
  }

  static void make_leaf(Bvh::Node& node, std::uint32_t begin, std::uint32_t count) {
    node.first = begin;
    node.count = count;
  }

  bool take_thread() {
    int n = free_threads_.load();
    while (n > 0)
      if (free_threads_.compare_exchange_weak(n, n - 1)) return true;
    return false;
  }

  int bin_of(float c, float lo, float scale) const {
    const int b = static_cast<int>((c - lo) * scale);
    return std::clamp(b, 0, bins() - 1);
  }
  int bins() const { return std::clamp(config_.bin_count, 2, kMaxBins); }

  Split find_sah_split(std::uint32_t begin, std::uint32_t end, const Aabb& bounds,
                       const Aabb& centroids) const {
    struct Bin {
      Aabb box;
      std::uint32_t count = 0;
    };
    const int n = bins();
    const glm::vec3 extent = centroids.extent();
    std::array<std::array<Bin, kMaxBins>, 3> bin{};
    glm::vec3 scale;
    for (int a = 0; a < 3; ++a) scale[a] = extent[a] > 0.0f ? static_cast<float>(n) / extent[a] : 0.0f;

    for (std::uint32_t i = begin; i < end; ++i) {
      const PrimRef& r = refs_[i];
      for (int a = 0; a < 3; ++a) {
        Bin& b = bin[a][bin_of(r.centroid[a], centroids.lo[a], scale[a])];
        b.box.grow(r.box);
        ++b.count;
      }
    }

    Split best;
    const float parent_area = bounds.area();
    float best_cost = std::numeric_limits<float>::infinity();
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0.0f)) continue;
      // Sweep from the right: area and count of bins [k + 1, n).
      std::array<float, kMaxBins> right_area{};
      std::array<std::uint32_t, kMaxBins> right_count{};
      Aabb acc;
      std::uint32_t cnt = 0;
      for (int k = n - 1; k > 0; --k) {
        acc.grow(bin[a][k].box);
        cnt += bin[a][k].count;
        right_area[k - 1] = acc.area();
        right_count[k - 1] = cnt;
      }
      acc = Aabb{};
      cnt = 0;
      for (int k = 0; k < n - 1; ++k) {
        acc.grow(bin[a][k].box);
        cnt += bin[a][k].count;
        if (cnt == 0 || right_count[k] == 0) continue;
        const float cost = acc.area() * static_cast<float>(cnt) +
                           right_area[k] * static_cast<float>(right_count[k]);
        if (cost < best_cost) {
          best_cost = cost;
          best = Split{a, k, 0.0f};
        }
      }
    }
    if (best.axis >= 0) {
      const float inv_area = parent_area > 0.0f ? 1.0f / parent_area : 0.0f;
      best.cost = config_.traversal_cost + config_.intersection_cost * best_cost * inv_area;
    }
    return best;
  }

  std::uint32_t partition(std::uint32_t begin, std::uint32_t end, const Aabb& centroids,
                          const Split& split) {
    const int a = split.axis;
    const float lo = centroids.lo[a];
    const float scale = static_cast<float>(bins()) / centroids.extent()[a];
    auto it = std::partition(refs_.begin() + begin, refs_.begin() + end, [&](const PrimRef& r) {
      return bin_of(r.centroid[a], lo, scale) <= split.bin;
    });
    return static_cast<std::uint32_t>(it - refs_.begin());
  }

  std::uint32_t median_split(std::uint32_t begin, std::uint32_t end, const Aabb& centroids) {
    const glm::vec3 e = centroids.extent();
    const int a = (e.x >= e.y && e.x >= e.z) ? 0 : (e.y >= e.z ? 1 : 2);
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(refs_.begin() + begin, refs_.begin() + mid, refs_.begin() + end,
                     [a](const PrimRef& x, const PrimRef& y) {
                       return x.centroid[a] < y.centroid[a] ||
                              (x.centroid[a] == y.centroid[a] && x.id < y.id);
                     });
    return mid;
  }

  const BvhConfig& config_;
  std::vector<PrimRef> refs_;
  std::vector<Bvh::Node> nodes_;
  std::atomic<std::uint32_t> node_count_{0};
  std::atomic<int> free_threads_{0};
};

}  // namespace

Bvh build_bvh(const Scene& scene, const BvhConfig& config) {
  if (config.bin_count < 2 || config.bin_count > kMaxBins)
    throw Error("--bvh-bins: must be between 2 and " + std::to_string(kMaxBins));
  if (config.max_leaf_size < 1 || config.max_leaf_size > 255)
    throw Error("--bvh-max-leaf: must be between 1 and 255");

  const auto start = std::chrono::steady_clock::now();
  std::vector<PrimRef> refs;
  refs.reserve(scene.triangles.size());
  std::uint32_t degenerate = 0;
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const Triangle& t = scene.triangles[i];
    if (is_degenerate(t)) {
      ++degenerate;
      continue;
    }
    PrimRef r;
    r.box.grow(t.v0);
    r.box.grow(t.v1);
    r.box.grow(t.v2);
    r.centroid = r.box.center();
    r.id = static_cast<std::uint32_t>(i);
    refs.push_back(r);
  }
  Bvh bvh = Builder(config, std::move(refs)).run();
  bvh.degenerate_count = degenerate;
  bvh.build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return bvh;
}

}  // namespace hrpp
