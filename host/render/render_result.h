// What both renderers (WavefrontRenderer and the CPU reference, host/cpu_render/) put into a
// RenderResult besides their own counters and times: the image size and the scene's stats
// before the first sample, the mean image after the last.
#pragma once

#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "render/render_scene.h"
#include "render/render_config.h"

namespace hrpp {

// A result of the config's image size whose stats describe the scene as the kernels read it:
// features compiled in, triangles, emissive triangles, delta lights, textures (with the
// textures feature on), their texel bytes and halvings.
RenderResult make_render_result(const RenderConfig& config, const RenderScene& rs);

// out.rgb = each pixel's radiance sum over `spp` samples (sum: one RGBA per pixel, A unused)
// divided by spp.
void set_mean_image(RenderResult& out, std::span<const glm::vec4> sum, std::uint32_t spp);

}  // namespace hrpp
