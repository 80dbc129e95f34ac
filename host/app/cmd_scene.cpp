// hrpp scene [SCENE] [--json] [--dump-triangles FILE]: what a scene holds and the BVH built
// over it.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/output_path.h"
#include "app/shared_options.h"
#include "bvh/binned_sah_builder.h"
#include "bvh/bvh_stats.h"
#include "bvh/gpu_layout.h"
#include "common/bytes.h"
#include "gpu/gpu_tracer.h"
#include "hrpp/predictor_config.h"
#include "render/render_scene.h"
#include "scene/load_scene.h"
#include "scene/scene_export.h"

namespace hrpp::app {
namespace {

struct SceneOptions {
  SharedOptions shared;
  bool json = false;
  std::string dump_triangles;
  std::string export_json;
};

nlohmann::json vec_json(const glm::vec3& v) { return {v.x, v.y, v.z}; }

// Bytes per triangle of the host's scene arrays and of each scene-sized device buffer of a
// render with HRPP off (the stats' "memory" names; the ray arrays, which scale with the image,
// are left out).
constexpr const char* kHostScene = "host scene (triangles and their shading)";

nlohmann::json bytes_per_triangle(const Scene& scene, const GpuBvh& layout) {
  const double n = static_cast<double>(std::max<std::size_t>(scene.triangles.size(), 1));
  const RenderScene rs = make_render_scene(scene, DefaultLighting{});
  const auto per = [&](std::size_t bytes) { return static_cast<double>(bytes) / n; };
  nlohmann::json j = {
      {kHostScene, static_cast<double>(sizeof(Triangle) + sizeof(TriangleShading))},
      {IndexedShading::kTriangleBuffer, per(rs.shading.triangles.size() * sizeof(gpu::ShadeIndex))},
      {IndexedShading::kVertexBuffer, per(rs.shading.vertices.size() * sizeof(gpu::ShadeVertex))},
      {IndexedShading::kAttributeBuffer,
       per(rs.shading.attributes.size() * sizeof(gpu::ShadeAttributes))}};
  for (const BufferNeed& b : GpuTracer::buffer_needs(layout, 0))
    if (b.bytes > 0) j[b.name] = per(b.bytes);
  return j;
}

void run_scene(const SceneOptions& o) {
  check_output_path(o.dump_triangles, "--dump-triangles");
  check_output_path(o.export_json, "--export-json");
  const Scene scene = load_scene(o.shared.scene);
  if (!o.dump_triangles.empty()) write_triangle_dump(scene, o.dump_triangles);
  if (!o.export_json.empty())
    write_file_atomically(o.export_json, scene_json(scene), "cannot write the scene");
  Bvh bvh = build_bvh(scene, o.shared.bvh);
  const BvhStats s = compute_bvh_stats(bvh, o.shared.bvh);
  const GpuBvh layout = make_gpu_layout(std::move(bvh), scene);  // the base tree freed as laid out

  std::size_t textured = 0, emissive = 0;
  for (const Material& m : scene.materials) {
    textured += m.base_color_texture >= 0;
    emissive += (m.emission.x > 0.0f || m.emission.y > 0.0f || m.emission.z > 0.0f);
  }
  nlohmann::json lights = nlohmann::json::object();
  for (const Light& l : scene.lights) {
    const char* name = name_in(kLightTypeNames, l.type);
    lights[name] = lights.value(name, 0) + 1;
  }

  nlohmann::json j = {
      {"scene", scene.name},
      {"triangles", scene.triangles.size()},
      {"degenerate_triangles", s.degenerate},
      {"materials", scene.materials.size()},
      {"textured_materials", textured},
      {"emissive_materials", emissive},
      {"textures", scene.textures.size()},
      {"lights", lights},
      {"cameras", scene.cameras.size()},
      {"default_camera", scene.default_camera},
      {"bounds", {{"lo", vec_json(layout.bounds.lo)}, {"hi", vec_json(layout.bounds.hi)}}},
      {"bvh",
       {{"bins", o.shared.bvh.bin_count},
        {"max_leaf_size_limit", o.shared.bvh.max_leaf_size},
        {"interior_nodes", s.interior_nodes},
        {"leaves", s.leaves},
        {"max_depth", s.max_depth},
        {"mean_leaf_depth", s.mean_leaf_depth},
        {"mean_leaf_size", s.mean_leaf_size},
        {"max_leaf_size", s.max_leaf_size},
        {"sah_cost", s.sah_cost},
        {"build_ms", s.build_ms},
        {"gpu_bytes", layout.bytes()}}},
      {"bytes_per_triangle", bytes_per_triangle(scene, layout)},
  };
  if (o.json) {
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::printf("scene       %s\n", scene.name.c_str());
  std::printf("triangles   %zu (%u degenerate, kept out of the BVH)\n", scene.triangles.size(),
              s.degenerate);
  std::printf("materials   %zu (%zu textured, %zu emissive), textures %zu\n",
              scene.materials.size(), textured, emissive, scene.textures.size());
  std::printf("lights      %zu%s%s\n", scene.lights.size(), scene.lights.empty() ? "" : " ",
              scene.lights.empty() ? "" : lights.dump().c_str());
  std::printf("cameras     %zu%s\n", scene.cameras.size(),
              scene.default_camera ? " (default, framing the bounds)" : "");
  std::printf("bounds      (%g, %g, %g) .. (%g, %g, %g)\n", layout.bounds.lo.x,
              layout.bounds.lo.y, layout.bounds.lo.z, layout.bounds.hi.x, layout.bounds.hi.y,
              layout.bounds.hi.z);
  std::printf("bvh         %u interior nodes, %u leaves, depth max %u mean %.2f\n",
              s.interior_nodes, s.leaves, s.max_depth, s.mean_leaf_depth);
  std::printf("            triangles/leaf mean %.2f max %u, SAH cost %.3f\n", s.mean_leaf_size,
              s.max_leaf_size, s.sah_cost);
  std::printf("            built in %.1f ms (%d bins, leaves <= %d), GPU layout %s\n",
              s.build_ms, o.shared.bvh.bin_count, o.shared.bvh.max_leaf_size,
              format_bytes(layout.bytes()).c_str());
  double device = 0.0;
  for (const auto& [name, b] : j["bytes_per_triangle"].items())
    if (name != kHostScene) device += b.get<double>();
  std::printf(
      "bytes       %.1f per triangle on the device (BVH and shading), %.1f in the host's "
      "scene\n",
      device, j["bytes_per_triangle"][kHostScene].get<double>());
}

}  // namespace

void add_scene_command(CLI::App& app) {
  auto o = std::make_shared<SceneOptions>();
  CLI::App* cmd = app.add_subcommand("scene", "Load a scene, build its BVH and print statistics");
  add_shared_options(cmd, o->shared, SharedGroup::kScene);
  cmd->add_flag("--json", o->json, "Print the statistics as JSON");
  cmd->add_option("--dump-triangles", o->dump_triangles,
                  "Write the triangles (9 float32 each, id order) to FILE");
  cmd->add_option("--export-json", o->export_json,
                  "Write the scene as loaded (triangles, materials, lights, cameras) as JSON to "
                  "FILE, for another renderer (study/cycles_reference.py)");
  cmd->add_option("--threads", o->shared.bvh.threads, "BVH build threads (0: all)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->callback([o] { run_scene(*o); });
}

}  // namespace hrpp::app
