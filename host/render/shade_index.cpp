#include "render/shade_index.h"

#include <cstring>

#include "common/error.h"
#include "surface_hit.h"

namespace hrpp {

static_assert(sizeof(gpu::ShadeIndex) == 16);       // 1 texel (load_shade_triangle)
static_assert(sizeof(gpu::ShadeVertex) == 16);      // 1 texel (load_shade_vertex)
static_assert(sizeof(gpu::ShadeAttributes) == 32);  // 2 texels (load_shade_attributes)

namespace {

template <class T>
std::uint64_t mix_words(std::uint64_t h, const T& record) {
  std::uint32_t w[sizeof(T) / 4];
  std::memcpy(w, &record, sizeof(T));
  for (std::uint32_t x : w) {
    h ^= x;
    h *= 0xFF51AFD7ED558CCDull;
    h ^= h >> 32;
  }
  return h;
}

template <class T>
bool same_bytes(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

std::uint64_t hash_of(const gpu::ShadeVertex& v, const gpu::ShadeAttributes& a) {
  return mix_words(mix_words(0x9E3779B97F4A7C15ull, v), a);
}

}  // namespace

gpu::ShadeTriangle IndexedShading::triangle(std::size_t id) const {
  const gpu::ShadeIndex& i = triangles[id];
  const auto attr = [&](std::uint32_t v) {
    return (i.material_data & HRPP_SHADE_ATTRIBUTES) != 0u ? attributes[v]
                                                           : gpu::default_shade_attributes();
  };
  return gpu::shade_triangle_of(i, vertices[i.corner0], vertices[i.corner1], vertices[i.corner2],
                                attr(i.corner0), attr(i.corner1), attr(i.corner2));
}

gpu::ShadeAttributes ShadeVertexTable::attributes(std::uint32_t index) const {
  return index < out_.attributes.size() ? out_.attributes[index] : gpu::default_shade_attributes();
}

std::uint64_t ShadeVertexTable::hash(std::uint32_t index) const {
  return hash_of(out_.vertices[index], attributes(index));
}

std::uint32_t ShadeVertexTable::insert(const ShadeCorner& c, bool store_attributes) {
  if (2 * (out_.vertices.size() + 1) > slots_.size()) grow();
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t s = hash_of(c.vertex, c.attributes) & mask;; s = (s + 1) & mask) {
    const std::uint32_t i = slots_[s];
    if (i != 0 && same_bytes(out_.vertices[i - 1], c.vertex) &&
        same_bytes(attributes(i - 1), c.attributes))
      return i - 1;
    if (i != 0) continue;
    if (out_.vertices.size() >= 0xFFFFFFFEu) throw Error("scene: over 2^32 - 2 shading vertices");
    if (store_attributes) {
      if (out_.attributes.size() != out_.vertices.size())
        throw Error("ShadeVertexTable: corners with attributes after those without (bug)");
      out_.attributes.push_back(c.attributes);
    }
    out_.vertices.push_back(c.vertex);
    slots_[s] = static_cast<std::uint32_t>(out_.vertices.size());
    return slots_[s] - 1;
  }
}

void ShadeVertexTable::grow() {
  std::vector<std::uint32_t> old = std::move(slots_);
  slots_.assign(old.empty() ? 1024 : 2 * old.size(), 0);
  const std::size_t mask = slots_.size() - 1;
  for (std::uint32_t i : old) {
    if (i == 0) continue;
    std::size_t s = hash(i - 1) & mask;
    while (slots_[s] != 0) s = (s + 1) & mask;
    slots_[s] = i;
  }
}

}  // namespace hrpp
