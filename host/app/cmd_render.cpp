// hrpp render [SCENE] --spp N --size WxH --max-depth D --seed S --out FILE --stats FILE: the
// wavefront path tracer (host/render/) on the Vulkan device, or with --backend cpu the CPU
// reference renderer (host/cpu_render/: the same image up to float rounding); prints per-kernel
// device time and per-ray-class counters, writes the image (EXR linear, PNG sRGB) and
// optionally the stats JSON.
#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "app/commands.h"
#include "app/cli_names.h"
#include "app/hrpp_options.h"
#include "app/output_path.h"
#include "app/render_session.h"
#include "app/provenance.h"
#include "app/shared_options.h"
#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "common/free_array.h"
#include "cpu_render/cpu_renderer.h"
#include "vk/vulkan_context.h"
#include "render/image_output.h"
#include "render/render_progress.h"
#include "render/render_stats.h"
#include "render/wavefront_renderer.h"
#include "reference/embree_tracer.h"
#include "scene/load_scene.h"

namespace hrpp::app {
namespace {

// Where the path tracer runs: the Vulkan device's kernels, or the CPU reference renderer.
enum class RenderBackend { kGpu, kCpu };
inline constexpr NameTable<RenderBackend, 2> kRenderBackendNames = {
    {{RenderBackend::kGpu, "gpu"}, {RenderBackend::kCpu, "cpu"}}};

// What the CPU backend traces with: its own scalar traversal, or Embree (rtcIntersect1 /
// rtcOccluded1), HRPP in front of either.
enum class CpuTracer { kScalar, kEmbree };
inline constexpr NameTable<CpuTracer, 2> kCpuTracerNames = {
    {{CpuTracer::kScalar, "scalar"}, {CpuTracer::kEmbree, "embree"}}};

struct RenderOptions {
  RenderBackend backend = RenderBackend::kGpu;
  CpuTracer cpu_tracer = CpuTracer::kScalar;
  SharedOptions shared;
  std::string size = "256x256";
  std::string out = "render.png";
  std::string stats;
  std::string default_environment = "0.5";
  std::string default_sun = "1.5";
  RenderConfig render;
  HrppOptions hrpp;
  RenderLimits limits;
  const CLI::Option* size_option = nullptr;  // given: --size and --spp beat the scene file's
  const CLI::Option* spp_option = nullptr;
};

// The image's metadata: provenance and the samples per pixel it holds.
ImageAttributes image_attributes(const std::string& device, const RenderResult& r) {
  ImageAttributes a = image_provenance(device);
  a.emplace_back("hrpp:samples", std::to_string(r.stats.frames.size()));
  return a;
}

// A device failure in the stats' "session": the error and the passes finished before it, of
// which the image holds the first stats.frames.size().
void add_failure(nlohmann::json& session, const RenderResult& r) {
  session["failed"] = true;
  session["error"] = r.failure;
  session["stopped_by"] = "device failure";
  session["passes_before_failure"] = r.passes_before_failure;
}

// A render's end: a line on stderr when it stopped early; after a signal, Interrupted (main
// returns 128 + the signal) once every output is written.
void finish_session(const RenderSession& session, const RenderOptions& o, const RenderResult& r) {
  const std::size_t passes = r.stats.frames.size();
  if (session.stopped_by().empty()) return;
  std::fprintf(stderr, "hrpp: %s: stopped after %zu of %u passes; %s holds their mean\n",
               session.stopped_by() == "signal"
                   ? (session.signal() == SIGINT ? "SIGINT" : "SIGTERM")
                   : "--time-limit",
               passes, o.render.spp, o.out.c_str());
  if (session.signal() != 0) throw Interrupted{session.signal()};
}

// A scene file's own image size and samples (pbrt's Film and Sampler) where the command line
// gives none.
void apply_scene_film(RenderOptions& o, const Scene& scene) {
  std::string from;
  if (scene.film_width > 0 && o.size_option->count() == 0) {
    o.render.width = scene.film_width;
    o.render.height = scene.film_height;
    from = std::to_string(scene.film_width) + "x" + std::to_string(scene.film_height);
  }
  if (scene.film_spp > 0 && o.spp_option->count() == 0) {
    o.render.spp = scene.film_spp;
    from += (from.empty() ? "" : ", ") + std::to_string(scene.film_spp) + " spp";
  }
  if (!from.empty())
    std::printf("film        %s from the scene file (--size, --spp override)\n", from.c_str());
}

// "WxH" → width, height; one-line error naming the flag otherwise.
void parse_size(const std::string& s, RenderConfig& c) {
  unsigned w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%u%c%u%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
      w == 0 || h == 0 || w > RenderConfig::kMaxSide || h > RenderConfig::kMaxSide)
    throw Error("--size \"" + s + "\": expected WxH with 1.." +
                std::to_string(RenderConfig::kMaxSide) + " each, e.g. 256x256");
  c.width = w;
  c.height = h;
}

// "none" → 0; "G" → (G, G, G); with `rgb` also "R,G,B"; each finite and >= 0. One-line error
// naming `flag` otherwise.
glm::vec3 parse_light(const std::string& s, const char* flag, bool rgb) {
  if (s == "none") return glm::vec3(0.0f);
  float c[3] = {0, 0, 0};
  char extra = 0;
  const int n = std::sscanf(s.c_str(), "%f,%f,%f%c", &c[0], &c[1], &c[2], &extra);
  const bool ok = n == 1 ? std::sscanf(s.c_str(), "%f%c", &c[0], &extra) == 1 : rgb && n == 3;
  if (n == 1) c[1] = c[2] = c[0];
  for (float v : c)
    if (!ok || !std::isfinite(v) || v < 0.0f || v > 1e30f)
      throw Error(std::string(flag) + " \"" + s + "\": expected none or " +
                  (rgb ? "a value G or R,G,B, e.g. 0.5 or 0.4,0.45,0.5" : "a value, e.g. 1.5") +
                  " (finite, >= 0)");
  return {c[0], c[1], c[2]};
}

// Ranges checked here rather than by CLI11 so that every bad value is one line and exit 1.
void check_range(const char* flag, std::uint32_t v, std::uint32_t lo, std::uint32_t hi) {
  if (v < lo || v > hi)
    throw Error(std::string(flag) + " " + std::to_string(v) + ": expected " + std::to_string(lo) +
                ".." + std::to_string(hi));
}

// The paper's figures per predicting ray class, and for hit-all rays (camera + bounce) and
// hit-any rays as a whole ("hit_all", "hit_any": the keys the limit study reads).
// `occupancy`: a class's table occupancy (the CPU renderer's per-thread tables: none given).
void add_class_summaries(const std::function<TableOccupancy(RayClass)>& occupancy_of,
                         const RenderStats& stats, const PredictorConfig& config,
                         std::string& text, nlohmann::json& j) {
  const bool baseline = config.count_baseline;
  RayClassStats all;
  TableOccupancy all_tables;
  for (RayClass c : kRayClasses) {
    if (!config.predicts(c)) continue;
    const RayClassStats& s = stats.classes[c];
    const TableOccupancy occupancy = occupancy_of(c);
    const PredictorSummary summary = summarize(s.predictor, s.counters, occupancy, baseline);
    text += format_summary(std::string("hrpp ") + ray_class_name(c), summary, query_kind(c));
    j[ray_class_name(c)] = predictor_summary_json(summary);
    if (query_kind(c) == QueryKind::kAny) {
      j["hit_any"] = j[ray_class_name(c)];
      continue;
    }
    all += s;
    all_tables += occupancy;
  }
  if (all.traces > 0)
    j["hit_all"] = predictor_summary_json(summarize(all.predictor, all.counters, all_tables,
                                                    baseline));
}

// --backend cpu: the CPU reference renderer, on every hardware thread, with HRPP inline in its
// traversal when on; the device options do not apply.
void run_cpu_render(const RenderOptions& o, const Scene& scene, const GpuBvh& bvh) {
  // The GPU stage's orders do not exist here: each ray probes, then traces, then inserts.
  if (o.render.predictor.enabled && (o.render.predictor.batch > 0 || o.render.predictor.serial))
    throw Error(std::string("--hrpp-config: ") +
                (o.render.predictor.batch > 0 ? "batch" : "serial") +
                ": the CPU backend predicts inline, one ray at a time, in its own order");
  std::unique_ptr<EmbreeTracer> embree;
  OutsideTracer outside;
  if (o.cpu_tracer == CpuTracer::kEmbree) {
    if (!embree_available()) throw Error("--cpu-tracer embree: this build has no Embree");
    embree = std::make_unique<EmbreeTracer>(scene);
    outside.closest = [e = embree.get()](const gpu::Ray& r) { return e->closest(r); };
    outside.occluded = [e = embree.get()](const gpu::Ray& r) { return e->occluded(r); };
  }
  const CpuRenderer renderer(scene, bvh, o.render, outside);
  DeviceInfo cpu;
  cpu.name = "CPU reference renderer";
  cpu.type = VK_PHYSICAL_DEVICE_TYPE_CPU;
  cpu.driver = std::to_string(CpuRenderer::threads()) + " threads, " +
               name_in(kCpuTracerNames, o.cpu_tracer) +
               (embree ? " (" + embree_version() + ")" : std::string());
  RenderSession session(o.render.spp, o.limits, [&](const RenderResult& r) {
    write_image(o.out, r.width, r.height, r.rgb, image_attributes(cpu.name, r), r.channels);
  });
  const RenderResult result = renderer.render(&session);
  write_image(o.out, result.width, result.height, result.rgb, image_attributes(cpu.name, result),
              result.channels);
  std::string hrpp_text;
  nlohmann::json hrpp_json = predictor_config_json(o.render.predictor);
  if (o.render.predictor.enabled)
    add_class_summaries([](RayClass) { return TableOccupancy{}; }, result.stats,
                        o.render.predictor, hrpp_text, hrpp_json);
  if (!o.stats.empty()) {
    nlohmann::json j = render_stats_json(scene.name, o.render, cpu, result);
    j["backend"] = name_in(kRenderBackendNames, RenderBackend::kCpu);
    j["cpu_tracer"] = name_in(kCpuTracerNames, o.cpu_tracer);
    j["hrpp_predictor"] = hrpp_json;
    j["session"] = session.json(static_cast<std::uint32_t>(result.stats.frames.size()));
    add_provenance(j);
    write_file_atomically(o.stats, j.dump(2) + "\n", "cannot write stats");
  }
  std::printf("scene       %s, %zu triangles\n", scene.name.c_str(), scene.triangles.size());
  std::printf("backend     cpu (%s, %s)\n", cpu.name.c_str(), cpu.driver.c_str());
  std::printf("%s", render_stats_text(o.render, result).c_str());
  std::printf("hrpp        %s\n%s",
              o.render.predictor.enabled ? describe(o.render.predictor).c_str() : "off",
              hrpp_text.c_str());
  std::printf("image       %s\n", o.out.c_str());
  if (!o.stats.empty()) std::printf("stats       %s\n", o.stats.c_str());
  finish_session(session, o, result);
}

// The flags' values checked and turned into the render configuration (before any file is read).
void check_render_options(RenderOptions& o) {
  parse_size(o.size, o.render);
  o.render.default_lighting.environment =
      parse_light(o.default_environment, "--default-environment", true);
  o.render.default_lighting.sun = parse_light(o.default_sun, "--default-sun", false).x;
  check_range("--spp", o.render.spp, 1, 1u << 20);
  check_range("--max-depth", o.render.max_depth, 1, RenderConfig::kMaxDepth);
  check_range("--rr-depth", o.render.rr_depth, 1, RenderConfig::kMaxDepth);
  check_range("--wavefront", o.render.wavefront_paths, 1, 1u << 24);
  check_image_format(o.out);
  check_output_path(o.out, "--out");
  check_output_path(o.stats, "--stats");
  if (o.backend == RenderBackend::kCpu && o.shared.nodes != NodeFormat::kBinary)
    throw Error(std::string("--bvh-nodes ") + node_format_name(o.shared.nodes) +
                ": the CPU backend (--backend cpu) traverses binary nodes");
  if (o.backend == RenderBackend::kCpu && o.shared.device_tracer != DeviceTracerKind::kCompute)
    throw Error("--tracer: the CPU backend (--backend cpu) traces on the CPU (--cpu-tracer)");
  // --ray-stats with the GPU backend: WavefrontRenderer refuses it.
  if (o.render.ray_stats && !is_exr(o.out))
    throw Error("--ray-stats: " + o.out + ": the layers need an .exr --out");
  if (o.backend != RenderBackend::kCpu && o.cpu_tracer != CpuTracer::kScalar)
    throw Error("--cpu-tracer: the CPU backend's (--backend cpu); the device traces with --tracer");
  o.render.tracer = o.shared.tracer;
  o.render.device_tracer = o.shared.device_tracer;
  o.render.predictor = o.hrpp.config(o.shared.device_tracer);
  check_compute_only(o.shared, {{"--reorder", o.render.reorder != RayOrder::kOff}});
}

void run_render(RenderOptions& o) {
  check_render_options(o);
  Scene scene = load_scene(o.shared.scene);
  apply_scene_film(o, scene);
  check_range("--spp", o.render.spp, 1, 1u << 20);
  if (o.backend == RenderBackend::kCpu)
    return run_cpu_render(
        o, scene,
        make_gpu_layout(build_bvh(scene, o.shared.bvh), scene, NodeLayout::kDfs, o.shared.nodes));
  // The host's peak (bench/README.md, "Memory per triangle"): the scene's shading is freed once
  // indexed, before the BVH is built, and the renderer frees the scene's triangles and the BVH's
  // arrays as they reach the device.
  RenderScene rs = make_render_scene(scene, o.render.default_lighting);
  free_array(scene.shading);
  GpuBvh bvh =
      make_gpu_layout(build_bvh(scene, o.shared.bvh), scene, NodeLayout::kDfs, o.shared.nodes);
  VulkanContext ctx(o.shared.vulkan);
  o.render.tracer = o.render.tracer.resolved_for(ctx.info());  // the stats name the device's
  const std::size_t triangles = scene.triangles.size();
  WavefrontRenderer renderer(ctx, scene, std::move(rs), bvh, o.render);

  RenderSession session(o.render.spp, o.limits, [&](const RenderResult& r) {
    write_image(o.out, r.width, r.height, r.rgb, image_attributes(ctx.info().name, r));
  });
  const RenderResult result = renderer.render(&session);
  const bool failed = !result.failure.empty();  // the device: nothing more is read from it
  if (!failed) check_validation_messages(ctx);
  write_image(o.out, result.width, result.height, result.rgb,
              image_attributes(ctx.info().name, result));
  // HRPP: the configuration and, per predicting ray class, the paper's figures.
  std::string hrpp_text;
  nlohmann::json hrpp_json = predictor_config_json(o.render.predictor);
  if (o.render.predictor.enabled)
    add_class_summaries(
        [&](RayClass c) { return failed ? TableOccupancy{} : renderer.predictor_occupancy(c); },
        result.stats, o.render.predictor, hrpp_text, hrpp_json);
  if (!o.stats.empty()) {
    nlohmann::json j = render_stats_json(scene.name, o.render, ctx.info(), result);
    j["backend"] = name_in(kRenderBackendNames, RenderBackend::kGpu);
    j["hrpp_predictor"] = hrpp_json;
    j["session"] = session.json(static_cast<std::uint32_t>(result.stats.frames.size()));
    if (failed) add_failure(j["session"], result);
    add_provenance(j);
    j["memory"] = memory_json(ctx.memory().report(), triangles);
    write_file_atomically(o.stats, j.dump(2) + "\n", "cannot write stats");
  }

  std::printf("scene       %s, %zu triangles\n", scene.name.c_str(), triangles);
  std::printf("device      %s\n", ctx.info().summary().c_str());
  std::printf("%s", render_stats_text(o.render, result).c_str());
  std::printf("hrpp        %s\n%s",
              o.render.predictor.enabled ? describe(o.render.predictor).c_str() : "off",
              hrpp_text.c_str());
  std::printf("memory      %s\n", memory_text(ctx.memory().report(), triangles).c_str());
  std::printf("image       %s\n", o.out.c_str());
  if (!o.stats.empty()) std::printf("stats       %s\n", o.stats.c_str());
  if (failed)
    throw Error(result.failure + "; " + o.out + " holds the mean of the " +
                std::to_string(result.stats.frames.size()) + " passes kept");
  finish_session(session, o, result);
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Render an image with the wavefront path tracer on the Vulkan device");
  add_shared_options(cmd, o->shared, SharedGroup::kDevice);
  cmd->add_option("--backend", o->backend,
                  "gpu: the wavefront kernels on the Vulkan device; cpu: the CPU reference "
                  "renderer (the same shading code, one path at a time; with --hrpp on, HRPP "
                  "inline in its traversal)")
      ->transform(one_of(kRenderBackendNames))
      ->default_str(name_in(kRenderBackendNames, o->backend));
  cmd->add_option("--cpu-tracer", o->cpu_tracer,
                  "--backend cpu: scalar (the CPU reference traversal) or embree (Embree's "
                  "rtcIntersect1/rtcOccluded1; with --hrpp on, HRPP in front of it)")
      ->transform(one_of(kCpuTracerNames))
      ->default_str(name_in(kCpuTracerNames, o->cpu_tracer));
  cmd->add_flag("--ray-stats", o->render.ray_stats,
               "--backend cpu, .exr: per-pixel ray statistics as layers camera, bounce, shadow "
               "(rays, interior; with --hrpp on predicted, verified; with count_baseline "
               "skipped)");
  o->spp_option = cmd->add_option("--spp", o->render.spp,
                                  "Samples per pixel (one wavefront pass each; default: the "
                                  "scene file's own where it has one, pbrt's Sampler)")
                       ->capture_default_str();
  cmd->add_option("--time-limit", o->limits.time_limit_s,
                  "Stop before a pass that would end more than SECONDS after the first pass began "
                  "(at most --spp passes; loading and set-up do not count)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--save-every", o->limits.save_every_s,
                  "Write the image of the passes so far at most every SECONDS (atomically)")
      ->check(CLI::NonNegativeNumber);
  o->size_option = cmd->add_option("--size", o->size,
                                   "Image size WxH (default: the scene file's own where it has "
                                   "one, pbrt's Film)")
                       ->capture_default_str();
  cmd->add_option("--max-depth", o->render.max_depth,
                  "Surface interactions per path (1: direct light only)")
      ->capture_default_str();
  cmd->add_option("--rr-depth", o->render.rr_depth,
                  "Russian roulette from this many surface interactions on (at or above "
                  "--max-depth: none)")
      ->capture_default_str();
  cmd->add_option("--seed", o->render.seed, "Random seed (same seed: same image, bit for bit)")
      ->capture_default_str();
  cmd->add_option("--camera", o->render.camera, "Camera index in the scene")
      ->capture_default_str();
  cmd->add_option("--out", o->out, "Image: .exr (linear float) or .png (sRGB, clamped)")
      ->capture_default_str();
  cmd->add_option("--stats", o->stats, "Write configuration, kernel times and counters as JSON");
  cmd->add_option("--wavefront", o->render.wavefront_paths, "Paths in flight at once")
      ->capture_default_str();
  cmd->add_option("--reorder", o->render.reorder,
                  "Sort each bounce's continuation rays before tracing them: off, or morton "
                  "(direction octant, then the origin's Morton code); the image is the same")
      ->transform(one_of(kRayOrderNames))
      ->default_str(ray_order_name(o->render.reorder));
  cmd->add_option("--light-sampling", o->render.light_sampling,
                  "How emissive triangles light a path: mis (light and BSDF sampling combined "
                  "by the power heuristic), light (light sampling alone) or bsdf (BSDF "
                  "sampling alone); the mean is the same")
      ->transform(one_of(kLightSamplingNames))
      ->default_str(name_in(kLightSamplingNames, o->render.light_sampling));
  cmd->add_option("--sampler", o->render.sampler,
                  "Random numbers of a path: sobol (Owen-scrambled Sobol points, decorrelated "
                  "per pixel) or independent (a hashed stream per path vertex)")
      ->transform(one_of(kSamplerNames))
      ->default_str(name_in(kSamplerNames, o->render.sampler));
  cmd->add_option("--default-environment", o->default_environment,
                  "Radiance of the uniform environment that lights a scene without any light "
                  "(most glTF models): G or R,G,B, or none")
      ->capture_default_str();
  cmd->add_option("--default-sun", o->default_sun,
                  "Irradiance of the sun (a directional light from above) that also lights "
                  "such a scene, or none; both none: such a scene renders black")
      ->capture_default_str();
  add_hrpp_options(cmd, o->hrpp);
  cmd->callback([o] { run_render(*o); });
}

}  // namespace hrpp::app
