#include "cpu_render/scene_lookups.h"

#include "material_lobes.h"
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

glm::vec3 sample_texture(const RenderScene& rs, int index, glm::vec2 uv, bool srgb) {
  const gpu::GpuTexture& t = rs.textures[static_cast<std::size_t>(index)];
  const gpu::TextureFootprint f = gpu::texture_footprint(t, uv);
  const auto texel = [&](std::uint32_t i) { return gpu::decode_texel(rs.texels[i], srgb); };
  return gpu::bilerp(texel(f.i00), texel(f.i10), texel(f.i01), texel(f.i11), f.f);
}

gpu::GpuMaterial textured_material(const RenderScene& rs, gpu::GpuMaterial m, glm::vec2 uv) {
  if (m.metallic_roughness_texture >= 0)
    m = gpu::with_metallic_roughness(m, sample_texture(rs, m.metallic_roughness_texture, uv,
                                                       false));
  if (m.emissive_texture >= 0) m.emission *= sample_texture(rs, m.emissive_texture, uv, true);
  return m;
}

}  // namespace hrpp
