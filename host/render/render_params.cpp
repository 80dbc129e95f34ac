#include "render/render_params.h"

#include <cmath>
#include <string>

#include <glm/glm.hpp>

#include "common/error.h"

namespace hrpp {

void check_render_config(const RenderConfig& c, const Scene& scene) {
  const std::string side = std::to_string(RenderConfig::kMaxSide);
  if (c.width == 0 || c.height == 0 || c.width > RenderConfig::kMaxSide ||
      c.height > RenderConfig::kMaxSide)
    throw Error("render size " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                " is outside 1x1.." + side + "x" + side);
  if (c.spp == 0) throw Error("spp (--spp) must be at least 1");
  if (c.max_depth == 0 || c.max_depth > RenderConfig::kMaxDepth)
    throw Error("max depth (--max-depth) must be 1.." + std::to_string(RenderConfig::kMaxDepth));
  if (c.wavefront_paths == 0) throw Error("wavefront paths (--wavefront) must be at least 1");
  if (c.device_tracer == DeviceTracerKind::kRayQuery && c.reorder != RayOrder::kOff)
    throw Error("--reorder: the ray-query tracer (--tracer rayquery) traces rays in their order");
  if (c.camera >= scene.cameras.size())
    throw Error("camera " + std::to_string(c.camera) + " (--camera) does not exist: the scene has " +
                std::to_string(scene.cameras.size()) + " (0.." +
                std::to_string(scene.cameras.size() - 1) + ")");
}

gpu::RenderParams make_render_params(const RenderConfig& c, const Camera& cam,
                                     const RenderScene& rs, std::uint32_t trace_any_group_rays) {
  gpu::RenderParams p{};
  p.width = c.width;
  p.height = c.height;
  p.seed = c.seed;
  p.max_depth = c.max_depth;
  const glm::vec3 f = glm::normalize(cam.forward);
  const glm::vec3 right_handed = glm::normalize(glm::cross(f, cam.up));
  const glm::vec3 up = glm::cross(right_handed, f);
  const glm::vec3 right = cam.mirrored ? -right_handed : right_handed;  // pbrt's left-handed
  // The image's own aspect ratio: a camera's stored aspect would stretch other image sizes.
  p.cam_position = glm::vec4(cam.position, std::tan(0.5f * cam.yfov));
  p.cam_forward = glm::vec4(f, static_cast<float>(c.width) / static_cast<float>(c.height));
  p.cam_up = glm::vec4(up, 0.0f);
  p.cam_right = glm::vec4(right, 0.0f);
  p.environment = glm::vec4(rs.environment, 0.0f);
  p.light_count = static_cast<std::uint32_t>(rs.lights.size());
  p.rr_depth = c.rr_depth;
  p.trace_any_group_rays = trace_any_group_rays;
  p.light_strategy = static_cast<std::uint32_t>(c.light_sampling);
  p.sampler_kind = static_cast<std::uint32_t>(c.sampler);
  return p;
}

}  // namespace hrpp
