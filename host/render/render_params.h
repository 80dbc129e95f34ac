// What both renderers (the wavefront renderer on the device, the CPU reference renderer) take
// from a RenderConfig: its checks, and the per-frame constants the shading code reads
// (gpu::RenderParams, shaders/shared/render_interface.h).
#pragma once

#include <cstdint>

#include "render/render_scene.h"
#include "render/render_config.h"
#include "render_interface.h"
#include "scene/scene.h"

namespace hrpp {

// Throws hrpp::Error naming the flag of the first bad field.
void check_render_config(const RenderConfig& c, const Scene& scene);

// Camera basis from cam (the image's own aspect ratio), environment and light count from rs.
// trace_any_group_rays: the shadow trace's rays per workgroup (the device's; 0 on the CPU).
gpu::RenderParams make_render_params(const RenderConfig& c, const Camera& cam,
                                     const RenderScene& rs, std::uint32_t trace_any_group_rays);

}  // namespace hrpp
