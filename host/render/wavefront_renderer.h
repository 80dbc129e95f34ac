// The wavefront path tracer (Laine, Karras, Aila, "Megakernels Considered Harmful: Wavefront
// Path Tracing on GPUs", HPG 2013): per sample pass and wavefront of pixels, kernels
//   render_generate → trace_closest → render_shade → trace_any → render_accumulate
// with the continuation rays looping back to trace_closest until --max-depth or Russian
// roulette ends every path. With HRPP on, each trace of a class that probes is the HRPP stage
// (hrpp_predict → trace kernel over the queue → hrpp_resolve), and an adaptive predictor
// (host/hrpp/adaptive_predictor.h) decides per frame which classes probe. The traces are the
// device tracer's (gpu/device_tracer.h; GpuTracer's kernels) on its own device-resident ray and
// hit arrays (so HRPP, when configured, predicts them too: one traversal in the project).
// render_shade fills the continuation and shadow queues with atomic counters; the shadow trace
// and render_accumulate are dispatched indirectly from the shadow queue, so a bounce is one
// command buffer; the host reads the queues (a few bytes) once per bounce.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>

#include "bvh/gpu_layout.h"
#include "hrpp/predictor_stats.h"
#include "trace/ray_class.h"
#include "render/pass_observer.h"
#include "render/render_config.h"
#include "render/render_scene.h"
#include "scene/scene.h"

namespace hrpp {

class VulkanContext;

class WavefrontRenderer {
 public:
  // Uploads the scene's shading data and creates the kernels specialised for its features.
  // Throws hrpp::Error on a bad configuration (naming the field) or when an array does not fit.
  WavefrontRenderer(VulkanContext& ctx, const Scene& scene, const GpuBvh& bvh,
                    const RenderConfig& config);
  // The same from a render scene made beforehand (make_render_scene, after which the caller may
  // free the scene's shading), freeing each host array as soon as the device holds its copy, so
  // the host never holds the scene, the BVH and their device copies at once: the scene's
  // triangles before the BVH's upload, the BVH's arrays after it, the render scene's shading
  // after its own. `scene` keeps its name, materials, lights and cameras; `bvh` its bounds.
  WavefrontRenderer(VulkanContext& ctx, Scene& scene, RenderScene rs, GpuBvh& bvh,
                    const RenderConfig& config);
  ~WavefrontRenderer();
  WavefrontRenderer(const WavefrontRenderer&) = delete;
  WavefrontRenderer& operator=(const WavefrontRenderer&) = delete;

  // Renders config.spp sample passes. `progress(samples_done)` is called after each pass.
  // Up to the config's spp passes; an observer may stop it after any pass (pass_observer.h),
  // and the image is then the mean of the passes done (stats.frames: one per pass). A device
  // failure (DeviceFailure: lost, out of memory) in a pass ends the render with the image and
  // stats the host kept last (RenderResult::failure); other errors throw.
  RenderResult render(PassObserver* observer = nullptr);

  const RenderScene& render_scene() const;
  // HRPP on: what a ray class's predictor table holds (it persists across samples).
  TableOccupancy predictor_occupancy(RayClass c) const;

 private:
  // How often at most the host keeps a copy of the image at a pass boundary (besides after the
  // first pass): what a lost device leaves. Its cost is one image download per interval.
  static constexpr std::chrono::milliseconds kKeepInterval{1000};

  // One sample pass over every pixel, its figures into `frame`.
  void run_pass(std::uint32_t sample, FrameStats& frame);

  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
