#include "render/wavefront_renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <string>

#include "common/error.h"
#include "gpu/compute_pipeline.h"
#include "gpu/embedded_shaders.h"
#include "gpu/storage_buffer.h"
#include "gpu/texel_view.h"
#include "gpu/vulkan_context.h"
#include "render_interface.h"

namespace hrpp {
namespace {

constexpr auto kBindingTypes = [] {
  std::array<VkDescriptorType, HRPP_RENDER_BINDING_COUNT> t{};
  t.fill(VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  for (int b : {HRPP_RENDER_BINDING_SHADE_TRIANGLES, HRPP_RENDER_BINDING_HITS,
                HRPP_RENDER_BINDING_MATERIALS, HRPP_RENDER_BINDING_LIGHTS,
                HRPP_RENDER_BINDING_RAY_TEXELS, HRPP_RENDER_BINDING_PATH_TEXELS})
    t[b] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  return t;
}();

void check_config(const RenderConfig& c, const Scene& scene) {
  if (c.width == 0 || c.height == 0 || c.width > 16384 || c.height > 16384)
    throw Error("render size " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                " is outside 1x1..16384x16384");
  if (c.spp == 0) throw Error("spp (--spp) must be at least 1");
  if (c.max_depth == 0 || c.max_depth > 1024) throw Error("max depth (--max-depth) must be 1..1024");
  if (c.wavefront_paths == 0) throw Error("wavefront paths (--wavefront) must be at least 1");
  if (c.camera >= scene.cameras.size())
    throw Error("camera " + std::to_string(c.camera) + " (--camera) does not exist: the scene has " +
                std::to_string(scene.cameras.size()) + " (0.." +
                std::to_string(scene.cameras.size() - 1) + ")");
}

template <class T>
StorageBuffer upload_array(VulkanContext& ctx, const std::vector<T>& items, const char* name) {
  StorageBuffer b(ctx, std::max<std::size_t>(items.size(), 1) * sizeof(T), name);
  if (!items.empty()) b.upload(items.data(), items.size() * sizeof(T));
  return b;
}

std::array<SpecializationConstant, HRPP_FEATURE_COUNT> specialization(const RenderFeatures& f) {
  std::array<SpecializationConstant, HRPP_FEATURE_COUNT> s{};
  for (std::uint32_t i = 0; i < HRPP_FEATURE_COUNT; ++i) s[i] = {i, f.on[i] ? 1u : 0u};
  return s;
}

void add_barrier(VkCommandBuffer cmd) {
  VkMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                    VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                    VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                           VK_PIPELINE_STAGE_HOST_BIT,
                       0, 1, &b, 0, nullptr, 0, nullptr);
}

}  // namespace

RayClassStats& RayClassStats::operator+=(const RayClassStats& o) {
  counters += o.counters;
  for (int i = 0; i < HRPP_PC_COUNT; ++i) predictor.c[i] += o.predictor.c[i];
  traces += o.traces;
  return *this;
}

FrameStats& FrameStats::operator+=(const FrameStats& o) {
  for (const auto& [k, ms] : o.kernels_ms) kernels_ms[k] += ms;
  closest += o.closest;
  shadow += o.shadow;
  camera_rays += o.camera_rays;
  bounce_rays += o.bounce_rays;
  wall_s += o.wall_s;
  return *this;
}

struct WavefrontRenderer::State {
  VulkanContext& ctx;
  RenderConfig cfg;
  RenderScene rs;
  GpuTracer tracer;
  std::uint32_t wave;  // paths per wavefront
  StorageBuffer params, paths, next_paths, next_rays, shadow_rays, shadows, image, queues;
  StorageBuffer shade_triangles, materials, lights, textures, texels;
  TexelView shade_view, material_view, light_view;
  TexelView ray_view, hit_view, path_view;  // over the tracer's arrays and `paths`
  std::array<SpecializationConstant, HRPP_FEATURE_COUNT> spec;
  ComputePipeline generate, shade, accumulate;
  KernelTimer timer;

  State(VulkanContext& c, const Scene& scene, const GpuBvh& bvh, const RenderConfig& config)
      : ctx(c),
        cfg((check_config(config, scene), config)),
        rs(make_render_scene(scene)),
        tracer(c, bvh, config.tracer, config.predictor),
        // One dispatch per kernel and wavefront: at most max_workgroup_count_x workgroups.
        wave(std::min({config.wavefront_paths, config.width * config.height,
                       c.info().max_workgroup_count_x * std::uint32_t{HRPP_RENDER_WORKGROUP_SIZE}})),
        params(c, sizeof(gpu::RenderParams), "render parameters"),
        paths(c, std::size_t{wave} * sizeof(gpu::PathState), "path states"),
        next_paths(c, std::size_t{wave} * sizeof(gpu::PathState), "continuation path states"),
        next_rays(c, std::size_t{wave} * sizeof(gpu::Ray), "continuation rays"),
        shadow_rays(c, std::size_t{wave} * sizeof(gpu::Ray), "shadow rays"),
        shadows(c, std::size_t{wave} * sizeof(gpu::ShadowRecord), "shadow records"),
        image(c, std::size_t{config.width} * config.height * sizeof(glm::vec4), "image"),
        queues(c, sizeof(gpu::RenderQueues), "render queues"),
        shade_triangles(upload_array(c, rs.triangles, "shading triangles")),
        materials(upload_array(c, rs.materials, "materials")),
        lights(upload_array(c, rs.lights, "lights")),
        textures(upload_array(c, rs.textures, "texture table")),
        texels(upload_array(c, rs.texels, "texels")),
        shade_view(c, shade_triangles),
        material_view(c, materials),
        light_view(c, lights),
        ray_view(c, tracer.ray_buffer(wave)),
        hit_view(c, tracer.hit_buffer()),
        path_view(c, paths),
        spec(specialization(rs.features)),
        generate(c, "render_generate", embedded_spirv("render_generate"), kBindingTypes,
                 sizeof(gpu::RenderPushConstants), spec),
        shade(c, "render_shade", embedded_spirv("render_shade"), kBindingTypes,
              sizeof(gpu::RenderPushConstants), spec),
        accumulate(c, "render_accumulate", embedded_spirv("render_accumulate"), kBindingTypes,
                   sizeof(gpu::RenderPushConstants), spec),
        timer(c, 4) {
    StorageBuffer& rays = tracer.ray_buffer(wave);
    for (ComputePipeline* p : {&generate, &shade, &accumulate}) {
      p->bind(HRPP_RENDER_BINDING_PARAMS, params);
      p->bind(HRPP_RENDER_BINDING_PATHS, paths);
      p->bind(HRPP_RENDER_BINDING_NEXT_PATHS, next_paths);
      p->bind(HRPP_RENDER_BINDING_RAYS, rays);
      p->bind(HRPP_RENDER_BINDING_HITS, hit_view);
      p->bind(HRPP_RENDER_BINDING_RAY_TEXELS, ray_view);
      p->bind(HRPP_RENDER_BINDING_PATH_TEXELS, path_view);
      p->bind(HRPP_RENDER_BINDING_NEXT_RAYS, next_rays);
      p->bind(HRPP_RENDER_BINDING_SHADOW_RAYS, shadow_rays);
      p->bind(HRPP_RENDER_BINDING_SHADOWS, shadows);
      p->bind(HRPP_RENDER_BINDING_IMAGE, image);
      p->bind(HRPP_RENDER_BINDING_QUEUES, queues);
      p->bind(HRPP_RENDER_BINDING_SHADE_TRIANGLES, shade_view);
      p->bind(HRPP_RENDER_BINDING_MATERIALS, material_view);
      p->bind(HRPP_RENDER_BINDING_LIGHTS, light_view);
      p->bind(HRPP_RENDER_BINDING_TEXTURES, textures);
      p->bind(HRPP_RENDER_BINDING_TEXELS, texels);
    }
    upload_params(scene.cameras[cfg.camera]);
  }

  void upload_params(const Camera& cam) {
    gpu::RenderParams p{};
    p.width = cfg.width;
    p.height = cfg.height;
    p.seed = cfg.seed;
    p.max_depth = cfg.max_depth;
    const glm::vec3 f = glm::normalize(cam.forward);
    const glm::vec3 right = glm::normalize(glm::cross(f, cam.up));
    const glm::vec3 up = glm::cross(right, f);
    // The image's own aspect ratio: a camera's stored aspect would stretch other image sizes.
    p.cam_position = glm::vec4(cam.position, std::tan(0.5f * cam.yfov));
    p.cam_forward = glm::vec4(f, static_cast<float>(cfg.width) / static_cast<float>(cfg.height));
    p.cam_up = glm::vec4(up, 0.0f);
    p.cam_right = glm::vec4(right, 0.0f);
    p.environment = glm::vec4(rs.environment, 0.0f);
    p.light_count = static_cast<std::uint32_t>(rs.lights.size());
    p.rr_depth = cfg.rr_depth;
    params.upload(&p, sizeof p);
  }

  // One dispatch of a render kernel over `count` items; returns its queue counters after
  // checking that every item finished (lavapipe loop limiter, DESIGN.md).
  gpu::RenderQueues run(ComputePipeline& kernel, const gpu::RenderPushConstants& pc,
                        FrameStats& stats) {
    const std::uint32_t groups =
        (pc.count + HRPP_RENDER_WORKGROUP_SIZE - 1) / HRPP_RENDER_WORKGROUP_SIZE;
    ctx.submit_and_wait(
        [&](VkCommandBuffer cmd) {
          vkCmdFillBuffer(cmd, queues.handle(), 0, VK_WHOLE_SIZE, 0);
          add_barrier(cmd);
          timer.reset(cmd);
          record_dispatch(cmd, kernel, &pc, groups, &timer);
          add_barrier(cmd);
        },
        kernel.name());
    for (const auto& [name, ms] : timer.read_ms()) stats.kernels_ms[name] += ms;
    gpu::RenderQueues q{};
    queues.download(&q, sizeof q);
    if (q.done != pc.count)
      throw Error(kernel.name() + ": only " + std::to_string(q.done) + " of " +
                  std::to_string(pc.count) +
                  " items finished: the driver's loop limiter or a lost dispatch");
    return q;
  }

  struct Copy {
    const StorageBuffer* from;
    const StorageBuffer* to;
    std::size_t bytes;
  };
  // Moves queue contents into the arrays the next kernel reads, on the device.
  void copy(std::initializer_list<Copy> copies) {
    ctx.submit_and_wait(
        [&](VkCommandBuffer cmd) {
          for (const Copy& c : copies) {
            const VkBufferCopy region{0, 0, c.bytes};
            vkCmdCopyBuffer(cmd, c.from->handle(), c.to->handle(), 1, &region);
          }
          add_barrier(cmd);
        },
        "render queue copy");
  }

  void trace(std::uint32_t n, bool any_hit, FrameStats& stats) {
    const GpuTraceResult r = tracer.trace_resident(n, any_hit);
    stats.kernels_ms[any_hit ? "trace_any" : "trace_closest"] += r.kernel_ms;
    RayClassStats& c = any_hit ? stats.shadow : stats.closest;
    c.counters += r.counters;
    for (int i = 0; i < HRPP_PC_COUNT; ++i) c.predictor.c[i] += r.predictor.c[i];
    ++c.traces;
  }

  // Paths of pixels [first, first + n) for one sample, to the end.
  void trace_wavefront(std::uint32_t first, std::uint32_t n, std::uint32_t sample,
                       FrameStats& stats) {
    StorageBuffer& rays = tracer.ray_buffer(wave);
    run(generate, {first, n, sample, 0}, stats);
    stats.camera_rays += n;
    for (std::uint32_t depth = 0; n > 0; ++depth) {
      if (depth >= cfg.max_depth)
        throw Error("render_shade: paths continued past the max depth (kernel bug)");
      trace(n, false, stats);
      if (depth > 0) stats.bounce_rays += n;
      const gpu::RenderQueues q = run(shade, {0, n, 0, depth}, stats);
      if (q.next_rays > n || q.shadow_rays > n)
        throw Error("render_shade: queue overflow (" + std::to_string(q.next_rays) + ", " +
                    std::to_string(q.shadow_rays) + " of " + std::to_string(n) + ")");
      if (q.shadow_rays > 0) {
        copy({{&shadow_rays, &rays, std::size_t{q.shadow_rays} * sizeof(gpu::Ray)}});
        trace(q.shadow_rays, true, stats);
        run(accumulate, {0, q.shadow_rays, 0, depth}, stats);
      }
      if (q.next_rays > 0) {
        copy({{&next_rays, &rays, std::size_t{q.next_rays} * sizeof(gpu::Ray)},
              {&next_paths, &paths, std::size_t{q.next_rays} * sizeof(gpu::PathState)}});
      }
      n = q.next_rays;
    }
  }
};

WavefrontRenderer::WavefrontRenderer(VulkanContext& ctx, const Scene& scene, const GpuBvh& bvh,
                                     const RenderConfig& config)
    : s_(std::make_unique<State>(ctx, scene, bvh, config)) {}

WavefrontRenderer::~WavefrontRenderer() = default;

const RenderScene& WavefrontRenderer::render_scene() const { return s_->rs; }

RenderResult WavefrontRenderer::render(const std::function<void(std::uint32_t)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  RenderResult out;
  out.width = s_->cfg.width;
  out.height = s_->cfg.height;
  RenderStats& stats = out.stats;
  stats.features = s_->rs.features.names_on();
  stats.triangles = s_->rs.triangles.size();
  stats.emissive_triangles = s_->rs.emissive_triangles;
  stats.delta_lights = s_->rs.delta_lights;
  stats.textures = s_->rs.features.on[HRPP_FEATURE_TEXTURES] ? s_->rs.textures.size() : 0;
  stats.texel_bytes = stats.textures ? s_->rs.texels.size() * sizeof(std::uint32_t) : 0;
  stats.texture_halvings = s_->rs.texture_halvings;
  const std::uint32_t pixels = out.width * out.height;
  if (s_->cfg.warm_up) {
    FrameStats discard;
    s_->tracer.warm_up();
    s_->trace_wavefront(0, std::min(pixels, 64u), 0, discard);
    s_->tracer.clear_predictor();  // HRPP: the warm-up paths leave nothing behind
  }
  s_->image.fill(0);
  for (std::uint32_t sample = 0; sample < s_->cfg.spp; ++sample) {
    const auto frame_start = std::chrono::steady_clock::now();
    FrameStats frame;
    for (const char* k : {"render_generate", "trace_closest", "render_shade", "trace_any",
                          "render_accumulate"})
      frame.kernels_ms[k] = 0.0;
    for (std::uint32_t first = 0; first < pixels; first += s_->wave)
      s_->trace_wavefront(first, std::min(s_->wave, pixels - first), sample, frame);
    frame.wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - frame_start).count();
    stats += frame;
    stats.frames.push_back(std::move(frame));
    if (progress) progress(sample + 1);
  }
  std::vector<glm::vec4> sum(pixels);
  s_->image.download(sum.data(), sum.size() * sizeof(glm::vec4));
  out.rgb.resize(std::size_t{pixels} * 3);
  const float inv = 1.0f / static_cast<float>(s_->cfg.spp);
  for (std::uint32_t i = 0; i < pixels; ++i)
    for (int c = 0; c < 3; ++c) out.rgb[std::size_t{i} * 3 + c] = sum[i][c] * inv;
  stats.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

TableOccupancy WavefrontRenderer::predictor_occupancy(bool any_hit) const {
  return s_->tracer.predictor_occupancy(any_hit);
}

}  // namespace hrpp
