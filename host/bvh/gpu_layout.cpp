#include "bvh/gpu_layout.h"

#include <string>

#include "bvh/wide_nodes.h"
#include "common/error.h"
#include "common/free_array.h"

namespace hrpp {
namespace {

class Flattener {
 public:
  Flattener(const Bvh& bvh, const Scene& scene, NodeLayout layout, GpuBvh& out)
      : bvh_(bvh), scene_(scene), layout_(layout), out_(out) {}

  // Returns the child reference of base node `index` placed under `parent` at `depth`.
  int place(std::uint32_t index, int parent, int depth) {
    const Bvh::Node& n = bvh_.nodes[index];
    if (n.is_leaf()) return leaf_ref(add_leaf(n.first, n.count, parent, depth));
    if (depth + 1 >= HRPP_STACK_SIZE)
      throw Error("BVH is deeper than the traversal stack (" + std::to_string(HRPP_STACK_SIZE) +
                  " levels)");
    const int self = static_cast<int>(out_.nodes.size());
    out_.nodes.emplace_back();
    // The links stay left/right whatever the numbering, so traversal visits the same nodes.
    int left = 0, right = 0;
    if (right_first(n)) {
      right = place(n.first + 1, self, depth + 1);
      left = place(n.first, self, depth + 1);
    } else {
      left = place(n.first, self, depth + 1);
      right = place(n.first + 1, self, depth + 1);
    }
    write_node(self, bvh_.nodes[n.first].bounds, bvh_.nodes[n.first + 1].bounds, left, right,
               parent, depth);
    return self;
  }

  // The triangle records in leaf order (the leaves' first_triangle made indices into them).
  void add_triangles(const std::vector<std::uint32_t>& prim_ids) {
    out_.triangles.reserve(prim_ids.size());  // every id is in one leaf's range
    for (gpu::BvhLeaf& leaf : out_.leaves) {
      const std::uint32_t first = leaf.first_triangle;
      leaf.first_triangle = static_cast<gpu::uint>(out_.triangles.size());
      for (std::uint32_t i = first; i < first + leaf.triangle_count; ++i) {
        const std::uint32_t id = prim_ids[i];
        const Triangle& t = scene_.triangles[id];
        gpu::TriangleRecord r{};
        r.v0 = t.v0;
        r.v1 = t.v1;
        r.v2 = t.v2;
        r.prim = id;
        out_.triangles.push_back(r);
      }
    }
  }

  // Root that is a single leaf (0 or 1 triangles): interior root, the leaf and an empty leaf.
  void place_lone_leaf() {
    const Bvh::Node& n = bvh_.nodes[0];
    out_.nodes.emplace_back();
    const int left = leaf_ref(add_leaf(n.first, n.count, 0, 1));
    const int right = leaf_ref(add_leaf(0, 0, 0, 1));
    write_node(0, n.bounds, n.bounds, left, right, -1, 0);
  }

 private:
  // Whether the right child's subtree is numbered first (right after its parent).
  bool right_first(const Bvh::Node& n) const {
    if (layout_ != NodeLayout::kDfsLargeFirst) return false;
    return bvh_.nodes[n.first + 1].bounds.area() > bvh_.nodes[n.first].bounds.area();
  }

  // The leaf's first_triangle is its first index into bvh.prim_ids until add_triangles.
  int add_leaf(std::uint32_t first, std::uint32_t count, int parent, int depth) {
    gpu::BvhLeaf leaf;
    leaf.first_triangle = first;
    leaf.triangle_count = count;
    leaf.parent = parent;
    leaf.depth = static_cast<gpu::uint>(depth);
    out_.leaves.push_back(leaf);
    return static_cast<int>(out_.leaves.size() - 1);
  }

  void write_node(int self, const Aabb& l, const Aabb& r, int left, int right, int parent,
                  int depth) {
    gpu::BvhNode& node = out_.nodes[self];
    node.left_xy = {l.lo.x, l.hi.x, l.lo.y, l.hi.y};
    node.right_xy = {r.lo.x, r.hi.x, r.lo.y, r.hi.y};
    node.lr_z = {l.lo.z, l.hi.z, r.lo.z, r.hi.z};
    node.link = {left, right, parent, depth};
  }

  const Bvh& bvh_;
  const Scene& scene_;
  NodeLayout layout_;
  GpuBvh& out_;
};

}  // namespace

std::span<const std::byte> GpuBvh::traced_nodes() const {
  switch (format()) {
    case NodeFormat::kWide4: return std::as_bytes(std::span(wide_nodes));
    case NodeFormat::kWide4Float: return std::as_bytes(std::span(wide_float_nodes));
    case NodeFormat::kBinary: break;
  }
  return std::as_bytes(std::span(nodes));
}

namespace {

// The nodes and leaves from `bvh`; then, with `consume` (the same Bvh), its nodes are freed
// before the triangle records are made and its triangle ids after: the host's peak holds the
// scene's triangles, the ids and the layout, not the base tree too.
GpuBvh layout(const Bvh& bvh, Bvh* consume, const Scene& scene, NodeLayout order,
              NodeFormat format) {
  GpuBvh out;
  if (bvh.nodes.empty()) throw Error("BVH has no nodes");
  out.bounds = bvh.nodes[0].bounds;
  out.nodes.reserve(bvh.nodes.size() / 2 + 1);
  out.leaves.reserve(bvh.nodes.size() / 2 + 2);
  Flattener f(bvh, scene, order, out);
  if (bvh.nodes[0].is_leaf() || bvh.nodes.size() == 1)
    f.place_lone_leaf();
  else
    f.place(0, -1, 0);
  if (consume) free_array(consume->nodes);
  f.add_triangles(bvh.prim_ids);
  if (consume) free_array(consume->prim_ids);
  if (format == NodeFormat::kWide4) out.wide_nodes = make_wide_nodes(out);
  if (format == NodeFormat::kWide4Float) out.wide_float_nodes = make_wide_float_nodes(out);
  return out;
}

}  // namespace

GpuBvh make_gpu_layout(const Bvh& bvh, const Scene& scene, NodeLayout order, NodeFormat format) {
  return layout(bvh, nullptr, scene, order, format);
}

GpuBvh make_gpu_layout(Bvh&& bvh, const Scene& scene, NodeLayout order, NodeFormat format) {
  return layout(bvh, &bvh, scene, order, format);
}

}  // namespace hrpp
