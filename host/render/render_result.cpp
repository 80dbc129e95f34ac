#include "render/render_result.h"

#include <cstddef>

namespace hrpp {

RenderResult make_render_result(const RenderConfig& config, const RenderScene& rs) {
  RenderResult out;
  out.width = config.width;
  out.height = config.height;
  RenderStats& stats = out.stats;
  stats.features = rs.features.names_on();
  stats.triangles = rs.triangle_count;
  stats.emissive_triangles = rs.emissive_triangles;
  stats.delta_lights = rs.delta_lights;
  stats.lighting = rs.lighting;
  stats.environment = rs.environment;
  stats.default_sun = rs.default_sun;
  stats.textures = rs.features.on[HRPP_FEATURE_TEXTURES] ? rs.textures.size() : 0;
  stats.texel_bytes = stats.textures ? rs.texels.size() * sizeof(std::uint32_t) : 0;
  stats.texture_halvings = rs.texture_halvings;
  return out;
}

void set_mean_image(RenderResult& out, std::span<const glm::vec4> sum, std::uint32_t spp) {
  out.rgb.resize(sum.size() * 3);
  const float inv = 1.0f / static_cast<float>(spp);
  for (std::size_t i = 0; i < sum.size(); ++i)
    for (int c = 0; c < 3; ++c) out.rgb[i * 3 + static_cast<std::size_t>(c)] = sum[i][c] * inv;
}

}  // namespace hrpp
