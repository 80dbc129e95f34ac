// The CPU reference renderer: a scalar path tracer that runs the wavefront renderer's own
// shading code (shaders/shared/path_vertex.h, material_lobes.h: the same camera rays, PCG
// streams, lobes, light samples, offsets and Russian roulette) one path at a time, tracing with
// the CPU traversal (trace/cpu_traversal.h, which answers as the trace kernels do). It adds
// light to a pixel in the order the kernels do (per sample and bounce: emission, then the shadow
// ray's payload), so its image equals the device's up to the device's own sqrt, sin, cos and
// pow, and the path decisions those can flip (tests/cpu_render_test.cpp). The ground truth of
// render_generate, render_shade and render_accumulate; `hrpp render --backend cpu`.
#pragma once

#include <functional>

#include "bvh/gpu_layout.h"
#include "render/render_scene.h"
#include "render/pass_observer.h"
#include "render/render_config.h"
#include "scene/scene.h"

namespace hrpp {

// An outside tracer in place of the CPU traversal (`--cpu-tracer embree`): the closest hit
// within a ray's [tmin, tmax], and whether anything lies there. Called from every render thread.
// Its node work is invisible: the stats count its rays and hits only.
struct OutsideTracer {
  std::function<gpu::Hit(const gpu::Ray&)> closest;
  std::function<bool(const gpu::Ray&)> occluded;
};

class CpuRenderer {
 public:
  // Throws hrpp::Error on a bad configuration, as WavefrontRenderer does. Of the config only
  // the image, samples, depths, seed, camera and HRPP apply (no wavefronts or tracer). HRPP on
  // (config.predictor.enabled): every ray of a predicting class probes before its traversal,
  // inline, through its thread's tables (host/hrpp/reference_predictor.h, one ray at a time),
  // kept across samples; no adaptive switch, batches or pilot schedule. With `outside` (both
  // functions set) the rays are traced by it instead of the CPU traversal, and a prediction that
  // does not answer its ray falls back to it (HRPP in front of Embree; fallback root).
  CpuRenderer(const Scene& scene, const GpuBvh& bvh, const RenderConfig& config,
              OutsideTracer outside = {});

  // Renders config.spp samples per pixel on threads() threads (one TaskPool for the whole
  // render). `progress(samples_done)` is called after each sample pass. The stats hold the
  // traversal counters per ray class (camera, bounce, shadow) and wall times; no kernel times.
  // An exception thrown while tracing, on any thread, reaches the caller.
  // As WavefrontRenderer::render: up to spp passes, an observer may stop it after any.
  RenderResult render(PassObserver* observer = nullptr) const;
  // The threads render() uses: every hardware thread (resolve_threads(0), common/task_pool.h).
  static int threads();

 private:
  const GpuBvh& bvh_;
  RenderConfig cfg_;
  OutsideTracer outside_;
  RenderScene rs_;
  gpu::RenderParams params_;
};

}  // namespace hrpp
