// What a render is asked for and what it gives back, for both renderers (WavefrontRenderer and
// the CPU reference, host/cpu_render/): the configuration, counters and device times per ray
// class and frame, and the image. Free of Vulkan.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/name_table.h"
#include "gpu/device_tracer_kind.h"
#include "gpu/gpu_tracer_config.h"
#include "gpu_types.h"
#include "hrpp/adaptive_predictor.h"
#include "hrpp/predictor_config.h"
#include "render/image_output.h"
#include "trace/ray_class.h"
#include "vk/timer_label.h"
#include "render_interface.h"
#include "hrpp_types.h"
#include "trace/ray_order.h"
#include "trace/traversal_counters.h"

namespace hrpp {

// What lit a render: the scene's own lights (emissive triangles, point, spot and directional
// lights, environments), or, for a scene without any, RenderConfig::default_lighting, or
// nothing (the image is black).
enum class Lighting : std::uint8_t { kScene, kDefault, kNone };
inline constexpr NameTable<Lighting, 3> kLightingNames = {
    {{Lighting::kScene, "scene"}, {Lighting::kDefault, "default"}, {Lighting::kNone, "none"}}};

// The light of a scene without any (most glTF models): a uniform environment, which alone would
// leave a white object invisible (a white furnace), and a sun from above that shades it.
struct DefaultLighting {
  // The direction the sun's light travels: down, from the +x +z side (glTF: +y is up, a model
  // faces +z).
  static constexpr glm::vec3 kSunDirection{-0.4f, -1.0f, -0.6f};  // normalised where used
  glm::vec3 environment{0.5f};  // radiance (--default-environment)
  float sun = 1.5f;             // irradiance (--default-sun); 0: none
};

// How emissive triangles light a path vertex (--light-sampling; HRPP_LIGHTS_*,
// shaders/shared/path_vertex.h): MIS of light and BSDF sampling, or one of them alone (kept for
// the unbiasedness tests and the error-against-time study).
enum class LightSampling : std::uint32_t {
  kMis = HRPP_LIGHTS_MIS,
  kLight = HRPP_LIGHTS_NEE,
  kBsdf = HRPP_LIGHTS_BSDF,
};
inline constexpr NameTable<LightSampling, 3> kLightSamplingNames = {
    {{LightSampling::kMis, "mis"},
     {LightSampling::kLight, "light"},
     {LightSampling::kBsdf, "bsdf"}}};

// Where a path's random numbers come from (--sampler; HRPP_SAMPLER_*,
// shaders/shared/sobol_sampler.h): Owen-scrambled Sobol pairs, or independent PCG streams.
enum class Sampler : std::uint32_t {
  kIndependent = HRPP_SAMPLER_INDEPENDENT,
  kSobol = HRPP_SAMPLER_SOBOL,
};
inline constexpr NameTable<Sampler, 2> kSamplerNames = {
    {{Sampler::kSobol, "sobol"}, {Sampler::kIndependent, "independent"}}};

struct RenderConfig {
  static constexpr std::uint32_t kMaxSide = 16384;  // image width and height
  static constexpr std::uint32_t kMaxDepth = 1024;  // max_depth

  std::uint32_t width = 256;
  std::uint32_t height = 256;
  std::uint32_t spp = 8;
  // Surface interactions per path; each samples one light and the BSDF (the ray leaving the
  // last one only finds emission), so light reaches the camera over up to max_depth + 1
  // segments (1: direct light only).
  std::uint32_t max_depth = 8;
  std::uint32_t rr_depth = 5;  // Russian roulette from this many interactions on
  std::uint32_t seed = 0;
  std::uint32_t camera = 0;                  // index into Scene::cameras
  std::uint32_t wavefront_paths = 1u << 18;  // paths in flight at once (memory bound)
  // Run every kernel once on a few paths before the timed frame: the first dispatch of a
  // pipeline JIT-compiles on lavapipe (docs/DEVICES.md, "Lavapipe"). The image and
  // the counters leave it out.
  bool warm_up = true;
  // The order in which each bounce's trace takes its rays (--reorder): kMorton sorts the
  // continuation rays on the GPU (host/gpu/ray_sorter.h) and the trace reads them through the
  // sort's order (no ray, hit or path state moves); the image is the same bit for bit, only the
  // trace's coherence changes. Not applied to a bounce that HRPP predicts.
  RayOrder reorder = RayOrder::kOff;
  // What lights a scene without any light (--default-environment, --default-sun); both zero:
  // nothing, and such a scene renders black.
  DefaultLighting default_lighting;
  LightSampling light_sampling = LightSampling::kMis;
  Sampler sampler = Sampler::kSobol;
  GpuTracerConfig tracer;
  // Which device tracer traces the wavefronts (--tracer): the BVH kernels, or the driver's ray
  // queries (HRPP off and rays in their order there; the context must have ray queries on).
  DeviceTracerKind device_tracer = DeviceTracerKind::kCompute;
  PredictorConfig predictor;  // HRPP: off unless predictor.enabled
  // Per-pixel statistics of the traced rays as RenderResult::channels (render/ray_stat_layers.h,
  // `--ray-stats`): the CPU renderer only.
  bool ray_stats = false;
};

// Device times by their names in reports (label_name: the ray sorter's kernels summed as
// "ray_sort", a sample's as "sample_<kernel>").
std::map<std::string, double> times_by_name(const std::map<TimerLabel, double>& kernels_ms);

// Counters and device time of one ray class (camera, bounce, shadow).
struct RayClassStats {
  TraversalCounters counters;               // verification included when the class probes
  gpu::PredictorCounters predictor{};       // HRPP on: summed over the class's traces
  std::uint64_t traces = 0;                 // traces (one per bounce and wavefront)
  std::uint64_t predicted_traces = 0;       // of those, through the HRPP stage
  std::uint64_t traced = 0;                 // rays the trace kernel traced (HRPP: the queues)
  std::uint64_t sampled = 0;                // HRPP sample frames: rays that ran the HRPP stage
  std::map<TimerLabel, double> kernels_ms;  // hrpp_predict, trace_*, hrpp_resolve (no class)

  RayClassStats& operator+=(const RayClassStats& o);
};

// One frame = one sample pass over every pixel: device time per kernel (timestamps around every
// dispatch, summed) and counters per ray class.
struct FrameStats {
  std::map<TimerLabel, double> kernels_ms;  // every dispatch, by label without the class
  PerClass<RayClassStats> classes;
  PerClass<ClassDecision> decisions;  // HRPP on: the adaptive predictor after this frame
  double wall_s = 0.0;                // host wall time

  // Camera + bounce rays (hit-all), as one class.
  RayClassStats closest() const;
  const RayClassStats& shadow() const { return classes[RayClass::kShadow]; }
  std::uint64_t camera_rays() const { return classes[RayClass::kCamera].counters.rays; }
  std::uint64_t bounce_rays() const { return classes[RayClass::kBounce].counters.rays; }
  FrameStats& operator+=(const FrameStats& o);
};

// The render: the sums over its frames, and each frame.
struct RenderStats : FrameStats {
  std::vector<std::string> features;  // specialization constants compiled in
  // What next-event estimation and texturing work with (render_scene.h).
  std::size_t triangles = 0;
  std::size_t emissive_triangles = 0;
  std::size_t delta_lights = 0;
  Lighting lighting = Lighting::kScene;
  glm::vec3 environment{0.0f};  // the constant environment's radiance (the default's included)
  float default_sun = 0.0f;     // Lighting::kDefault: the sun's irradiance
  std::size_t textures = 0;
  std::size_t texel_bytes = 0;
  int texture_halvings = 0;
  std::vector<FrameStats> frames;  // one per sample pass
};

struct RenderResult {
  std::uint32_t width = 0, height = 0;
  std::vector<float> rgb;  // linear radiance, mean over the samples, rows top down
  std::vector<ImageChannel> channels;  // RenderConfig::ray_stats: the rays' per-pixel statistics
  RenderStats stats;
  // A render the device failed mid-way (lost, out of memory): the error's one line, and how many
  // passes had finished when it came; rgb and stats are those of the last pass boundary the host
  // kept (WavefrontRenderer: the first pass, then at most once a second), stats.frames.size()
  // passes. Empty when the render ran to its end.
  std::string failure;
  std::uint32_t passes_before_failure = 0;
};

}  // namespace hrpp
