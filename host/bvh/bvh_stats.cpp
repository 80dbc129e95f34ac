#include "bvh/bvh_stats.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace hrpp {

BvhStats compute_bvh_stats(const Bvh& bvh, const BvhConfig& config) {
  BvhStats s;
  s.references = static_cast<std::uint32_t>(bvh.prim_ids.size());
  std::vector<std::uint32_t> ids = bvh.prim_ids;
  std::sort(ids.begin(), ids.end());
  s.triangles = static_cast<std::uint32_t>(std::unique(ids.begin(), ids.end()) - ids.begin());
  s.degenerate = bvh.degenerate_count;
  s.build_ms = bvh.build_ms;
  if (bvh.nodes.empty()) return s;

  const double root_area = bvh.nodes[0].bounds.area();
  double interior_area = 0.0, leaf_area = 0.0, depth_sum = 0.0;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> stack{{0u, 0u}};  // node, depth
  while (!stack.empty()) {
    const auto [index, depth] = stack.back();
    stack.pop_back();
    const Bvh::Node& n = bvh.nodes[index];
    if (n.is_leaf() || bvh.nodes.size() == 1) {  // a lone root is a leaf, even empty
      ++s.leaves;
      depth_sum += depth;
      s.max_depth = std::max(s.max_depth, depth);
      s.max_leaf_size = std::max(s.max_leaf_size, n.count);
      leaf_area += static_cast<double>(n.count) * n.bounds.area();
    } else {
      ++s.interior_nodes;
      interior_area += n.bounds.area();
      stack.push_back({n.first + 1, depth + 1});
      stack.push_back({n.first, depth + 1});
    }
  }
  s.mean_leaf_depth = depth_sum / s.leaves;
  s.mean_leaf_size = static_cast<double>(s.references) / s.leaves;
  if (root_area > 0.0)
    s.sah_cost = (config.traversal_cost * interior_area + config.intersection_cost * leaf_area) /
                 root_area;
  return s;
}

}  // namespace hrpp
