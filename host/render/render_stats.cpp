#include "render/render_stats.h"

#include <cstdio>

#include "common/bytes.h"
#include "common/peak_rss.h"
#include "hrpp/predictor_stats.h"
#include "hrpp_types.h"

namespace hrpp {
namespace {

using nlohmann::json;

json counters_json(const TraversalCounters& c) {
  return json{{"rays", c.rays},
              {"interior_visited", c.interior_visited},
              {"leaves_visited", c.leaves_visited},
              {"triangles_tested", c.triangles_tested},
              {"hits", c.hits}};
}

json class_json(const RayClassStats& s, bool hrpp_on) {
  json j = counters_json(s.counters);
  j["trace_dispatches"] = s.traces;
  j["kernels_ms"] = times_by_name(s.kernels_ms);
  if (hrpp_on) {
    json p;
    for (const CounterKey& k : kPredictorCounterKeys) p[k.key] = s.predictor.c[k.index];
    p["predicted_traces"] = s.predicted_traces;
    p["traced"] = s.traced;
    p["sampled"] = s.sampled;
    j["hrpp"] = p;
  }
  return j;
}

json decision_json(const ClassDecision& d) {
  return json{{"mode", probe_name(d.mode)},   {"reason", reason_name(d.reason)},
              {"gain_ms", d.gain_ms},         {"off_ms_per_ray", d.off_ms_per_ray},
              {"dispatch_ms", d.dispatch_ms}, {"sample_stride", d.sample_stride},
              {"confidence", d.confidence},   {"next", probe_name(d.next)}};
}

// The per-class figures of a frame or a render.
void add_classes(json& j, const FrameStats& f, bool hrpp_on) {
  j["rays"] = {{"camera", f.camera_rays()},
               {"bounce", f.bounce_rays()},
               {"shadow", f.shadow().counters.rays}};
  j["closest"] = class_json(f.closest(), hrpp_on);
  j["shadow"] = class_json(f.shadow(), hrpp_on);
  for (RayClass c : kRayClasses) j["classes"][ray_class_name(c)] = class_json(f.classes[c], hrpp_on);
}

json frame_json(const FrameStats& f, bool hrpp_on) {
  json j{{"kernels_ms", times_by_name(f.kernels_ms)}, {"wall_s", f.wall_s}};
  add_classes(j, f, hrpp_on);
  if (hrpp_on)
    for (RayClass c : kRayClasses) j["hrpp_decisions"][ray_class_name(c)] = decision_json(f.decisions[c]);
  return j;
}

double per_ray(std::uint64_t v, std::uint64_t rays) {
  return rays ? static_cast<double>(v) / static_cast<double>(rays) : 0.0;
}

}  // namespace

nlohmann::json render_stats_json(const std::string& scene, const RenderConfig& config,
                                 const DeviceInfo& device, const RenderResult& result) {
  const RenderStats& s = result.stats;
  const bool hrpp_on = config.predictor.enabled;
  TraversalCounters total = s.closest().counters;
  total += s.shadow().counters;
  double kernels_total = 0.0;
  for (const auto& [k, ms] : s.kernels_ms) kernels_total += ms;
  json j;
  j["config"] = {{"scene", scene},
                 {"width", config.width},
                 {"height", config.height},
                 {"spp", config.spp},
                 {"max_depth", config.max_depth},
                 {"rr_depth", config.rr_depth},
                 {"seed", config.seed},
                 {"camera", config.camera},
                 {"wavefront_paths", config.wavefront_paths},
                 {"rays_per_invocation", config.tracer.rays_per_invocation},
                 {"reorder", ray_order_name(config.reorder)},
                 {"light_sampling", name_in(kLightSamplingNames, config.light_sampling)},
                 {"sampler", name_in(kSamplerNames, config.sampler)},
                 {"hrpp", hrpp_on ? "on" : "off"},
                 {"frame",
                  "one sample pass over every pixel; the top level sums the frames, "
                  "\"frames\" lists each"}};
  j["device"] = {{"name", device.name},
                 {"type", device.type_name()},
                 {"driver", device.driver},
                 {"subgroup_size", device.subgroup_size},
                 {"denorm_preserve", device.denorm_preserve},
                 {"timestamps", device.timestamps}};
  j["features"] = s.features;
  j["scene"] = {{"triangles", s.triangles},
                {"emissive_triangles", s.emissive_triangles},
                {"delta_lights", s.delta_lights},
                {"lighting", name_in(kLightingNames, s.lighting)},
                {"environment", {s.environment.r, s.environment.g, s.environment.b}},
                {"default_sun", s.default_sun},
                {"textures", s.textures},
                {"texel_bytes", s.texel_bytes},
                {"texture_halvings", s.texture_halvings}};
  j["kernels_ms"] = times_by_name(s.kernels_ms);
  j["kernels_ms_total"] = kernels_total;
  add_classes(j, s, hrpp_on);
  j["totals"] = counters_json(total);
  j["wall_s"] = s.wall_s;
  j["frames"] = json::array();
  for (const FrameStats& f : s.frames) j["frames"].push_back(frame_json(f, hrpp_on));
  return j;
}

std::string render_stats_text(const RenderConfig& config, const RenderResult& result) {
  const RenderStats& s = result.stats;
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "features    %s\n",
                s.features.empty() ? "(none)" : json(s.features).dump().c_str());
  out += line;
  if (s.lighting != Lighting::kScene) {
    if (s.lighting == Lighting::kNone)
      std::snprintf(line, sizeof line,
                    "lighting    none: the scene has no light and "
                    "--default-environment and --default-sun are none, so "
                    "the image is black\n");
    else
      std::snprintf(line, sizeof line,
                    "lighting    the scene has no light: a uniform environment of radiance "
                    "(%g, %g, %g) and a sun of irradiance %g from above light it "
                    "(--default-environment, --default-sun)\n",
                    s.environment.r, s.environment.g, s.environment.b, s.default_sun);
    out += line;
  }
  double total = 0.0;
  for (const auto& [k, ms] : times_by_name(s.kernels_ms)) {
    std::snprintf(line, sizeof line, "kernel      %-18s %10.3f ms\n", k.c_str(), ms);
    out += line;
    total += ms;
  }
  std::snprintf(line, sizeof line, "kernel      %-18s %10.3f ms (wall %.3f s)\n", "total", total,
                s.wall_s);
  out += line;
  for (RayClass cls : kRayClasses) {
    const TraversalCounters& c = s.classes[cls].counters;
    std::snprintf(line, sizeof line,
                  "%-11s %llu rays, %llu hits; per ray %.2f interior nodes, %.2f leaves, "
                  "%.2f triangles\n",
                  ray_class_name(cls), static_cast<unsigned long long>(c.rays),
                  static_cast<unsigned long long>(c.hits), per_ray(c.interior_visited, c.rays),
                  per_ray(c.leaves_visited, c.rays), per_ray(c.triangles_tested, c.rays));
    out += line;
  }
  std::snprintf(line, sizeof line, "rays        camera %llu, bounce %llu, shadow %llu (%ux%u, %u spp)\n",
                static_cast<unsigned long long>(s.camera_rays()),
                static_cast<unsigned long long>(s.bounce_rays()),
                static_cast<unsigned long long>(s.shadow().counters.rays), config.width,
                config.height, config.spp);
  out += line;
  return out;
}

json memory_json(const MemoryReport& memory, std::size_t triangles) {
  json buffers = json::object();
  for (const auto& [name, bytes] : memory.buffers) buffers[name] = bytes;
  json j{{"buffers", buffers},
         {"total_bytes", memory.total},
         {"peak_bytes", memory.peak},
         {"heap_bytes", memory.heap},
         {"mode", memory.placement.mode},
         {"placement", placement_json(memory.placement)}};
  if (triangles == 0) return j;
  const double n = static_cast<double>(triangles);
  const auto per = [&](std::uint64_t bytes) { return static_cast<double>(bytes) / n; };
  json per_buffer = json::object();
  for (const auto& [name, bytes] : memory.buffers) per_buffer[name] = per(bytes);
  const std::uint64_t rss = peak_rss_bytes();
  j["bytes_per_triangle"] = per_buffer;
  j["total_bytes_per_triangle"] = per(memory.total);
  j["host_peak_rss_bytes"] = rss;
  j["host_peak_rss_bytes_per_triangle"] = per(rss);
  return j;
}

json placement_json(const MemoryPlacement& placement) {
  json roles = json::object();
  for (const auto& [role, t] : placement.roles)
    roles[role] = {{"type", t.type}, {"heap", t.heap}, {"flags", t.flags}, {"mapped", t.mapped}};
  return roles;
}

std::string placement_text(const MemoryPlacement& placement) {
  std::string s = placement.mode + ":";
  for (const auto& [role, t] : placement.roles)
    s += std::string(s.back() == ':' ? " " : ", ") + role + " buffers in type " +
         std::to_string(t.type) + " (" + t.flags + ") heap " + std::to_string(t.heap);
  return s;
}

std::string memory_text(const MemoryReport& memory, std::size_t triangles) {
  std::string largest;
  std::uint64_t most = 0;
  for (const auto& [name, bytes] : memory.buffers)
    if (bytes > most) {
      most = bytes;
      largest = name;
    }
  std::string s = format_bytes(memory.total) + " in " + std::to_string(memory.buffers.size()) +
                  " buffers (peak " + format_bytes(memory.peak) + ", device heap " +
                  format_bytes(memory.heap) + ")";
  if (!largest.empty()) s += "; largest " + largest + " " + format_bytes(most);
  s += "; " + placement_text(memory.placement);
  if (triangles == 0) return s;
  const std::uint64_t rss = peak_rss_bytes();
  char per[96];
  std::snprintf(per, sizeof per, "; %.1f bytes/triangle, host peak RSS ",
                static_cast<double>(memory.total) / static_cast<double>(triangles));
  s += per + format_bytes(rss);
  std::snprintf(per, sizeof per, " (%.1f bytes/triangle)",
                static_cast<double>(rss) / static_cast<double>(triangles));
  return s + per;
}

}  // namespace hrpp
