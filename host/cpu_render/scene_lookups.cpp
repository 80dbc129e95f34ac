#include "cpu_render/scene_lookups.h"

#include "surface_hit.h"

namespace hrpp {

std::uint32_t pick_light(const RenderScene& rs, float u, float& prob) {
  std::uint32_t lo = 0, hi = static_cast<std::uint32_t>(rs.lights.size()) - 1;
  for (int step = 0; step < 32 && lo < hi; ++step) {
    const std::uint32_t mid = (lo + hi) / 2;
    if (u < rs.lights[mid].cdf) hi = mid;
    else lo = mid + 1;
  }
  prob = rs.lights[lo].cdf - (lo > 0 ? rs.lights[lo - 1].cdf : 0.0f);
  return lo;
}

float pick_prob(const RenderScene& rs, std::uint32_t i) {
  return rs.lights[i].cdf - (i > 0 ? rs.lights[i - 1].cdf : 0.0f);
}

glm::vec3 sample_texture(const RenderScene& rs, int index, glm::vec2 uv) {
  const gpu::GpuTexture& t = rs.textures[static_cast<std::size_t>(index)];
  const gpu::TextureFootprint f = gpu::texture_footprint(t, uv);
  return gpu::bilerp(gpu::decode_texel(rs.texels[f.i00]), gpu::decode_texel(rs.texels[f.i10]),
                     gpu::decode_texel(rs.texels[f.i01]), gpu::decode_texel(rs.texels[f.i11]),
                     f.f);
}

}  // namespace hrpp
