// The scene as the render kernels read it (shaders/shared/render_interface.h): shading data per
// triangle id, materials, the light list for next-event estimation with its selection cdf, the
// textures in one texel array (lavapipe has no descriptor indexing), and the features the scene
// needs, which select the kernels' specialization constants.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "render/render_config.h"
#include "render/shade_index.h"
#include "render_interface.h"
#include "scene/scene.h"

namespace hrpp {

// What a scene needs compiled in, in HRPP_FEATURE_* order.
struct RenderFeatures {
  std::array<bool, HRPP_FEATURE_COUNT> on{};

  static const char* name(int feature);       // "textures", "emissive_triangles", ...
  std::vector<std::string> names_on() const;  // for the stats
};

struct RenderScene {
  std::size_t triangle_count = 0;
  IndexedShading shading;  // by triangle id (WavefrontRenderer may free it once uploaded)
  std::vector<gpu::GpuMaterial> materials;
  std::vector<gpu::GpuLight> lights;  // cdf ascending, last = 1
  std::vector<gpu::GpuTexture> textures;
  std::vector<std::uint32_t> texels;  // RGBA8, R in the low byte
  glm::vec3 environment{0.0f};        // sum of the constant environment lights
  Lighting lighting = Lighting::kScene;
  float default_sun = 0.0f;  // Lighting::kDefault: the sun's irradiance
  RenderFeatures features;
  int texture_halvings = 0;  // times every texture was halved to fit the texel budget
  std::size_t emissive_triangles = 0;
  std::size_t delta_lights = 0;  // point, spot, directional
};

// Area-quad lights are sampled through their emissive triangles (every loader adds the quad as
// emissive geometry). Lights are chosen by power. A scene with no light that emits is lit by
// `lighting` (Lighting::kDefault: its environment and sun, a directional light), or by nothing
// when both are zero (kNone). Textures whose RGBA8 texels exceed `texel_budget_bytes` are
// halved (box filter) until they fit.
RenderScene make_render_scene(const Scene& scene, const DefaultLighting& lighting,
                              std::size_t texel_budget_bytes = 64u << 20);

}  // namespace hrpp
