// The scene's shading data indexed (shaders/shared/render_interface.h: ShadeIndex, ShadeVertex,
// ShadeAttributes): a corner (position, light, normal, colour, uv) that several triangles share
// is stored once. Corners are merged only when their bytes are equal, so the ShadeTriangle
// assembled from the records (shade_triangle_of) is bit for bit the corners' own.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render_interface.h"

namespace hrpp {

struct IndexedShading {
  std::vector<gpu::ShadeIndex> triangles;  // by triangle id
  std::vector<gpu::ShadeVertex> vertices;
  // By vertex, for the vertices below attributes.size(): the corners of the triangles with
  // HRPP_SHADE_ATTRIBUTES, which are numbered first; every other vertex's are the defaults.
  std::vector<gpu::ShadeAttributes> attributes;

  gpu::ShadeTriangle triangle(std::size_t id) const;  // as render_shade's load_shade_triangle

  // The device buffers' names (the stats' "memory" object).
  static constexpr const char* kTriangleBuffer = "shading triangles";
  static constexpr const char* kVertexBuffer = "shading vertices";
  static constexpr const char* kAttributeBuffer = "shading vertex attributes";
};

// One corner of a triangle, the key of the vertex table.
struct ShadeCorner {
  gpu::ShadeVertex vertex;
  gpu::ShadeAttributes attributes;
};

// Fills IndexedShading::vertices and attributes: one record per distinct corner. The corners
// with attributes are inserted first (insert(c, true)), then those without (insert(c, false):
// their attributes are the defaults and are not stored). Its only temporary is an
// open-addressing table of vertex indices, at most half full.
class ShadeVertexTable {
 public:
  explicit ShadeVertexTable(IndexedShading& out) : out_(out) {}

  // The vertex index of a corner equal to `c`, added when there is none.
  std::uint32_t insert(const ShadeCorner& c, bool store_attributes);

 private:
  gpu::ShadeAttributes attributes(std::uint32_t index) const;
  std::uint64_t hash(std::uint32_t index) const;
  void grow();

  IndexedShading& out_;
  std::vector<std::uint32_t> slots_;  // 1 + vertex index; 0: empty
};

}  // namespace hrpp
