// load_scene(): dispatch on the scene spec, then the checks and defaults every scene gets.
#include "scene/load_scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "scene/obj_file.h"
#include "scene/ply_file.h"
#include "scene/pbrt_loader.h"

namespace hrpp {
namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  for (std::size_t i = 0; i < suffix.size(); ++i) {
    const auto a = static_cast<unsigned char>(s[s.size() - suffix.size() + i]);
    if (std::tolower(a) != static_cast<unsigned char>(suffix[i])) return false;
  }
  return true;
}

const char* const kBuiltins[] = {"builtin:cornell"};

std::string builtin_list() {
  std::string s;
  for (const char* b : kBuiltins) s += (s.empty() ? "" : ", ") + std::string(b);
  return s;
}

// Names of the manifests in HRPP_SCENES_DIR, for the "unknown scene" message.
std::string manifest_list() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(HRPP_SCENES_DIR, ec)) {
    const std::string f = e.path().filename().string();
    if (ends_with(f, ".scene.json")) names.push_back(f.substr(0, f.size() - 11));
  }
  std::sort(names.begin(), names.end());
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s.empty() ? "none" : s;
}

// scenes/fetched/<folder>/NAME.pbrt (tools/fetch-scenes.sh puts the Killeroos there).
std::optional<std::filesystem::path> fetched_pbrt(const std::string& name) {
  std::error_code ec;
  const std::filesystem::path fetched = std::filesystem::path(HRPP_SCENES_DIR) / "fetched";
  for (const auto& e : std::filesystem::directory_iterator(fetched, ec)) {
    const std::filesystem::path f = e.path() / (name + ".pbrt");
    if (e.is_directory(ec) && std::filesystem::exists(f, ec)) return f;
  }
  return std::nullopt;
}

Scene dispatch(const std::string& spec) {
  if (spec.rfind("builtin:", 0) == 0) {
    if (spec == "builtin:cornell") return builtin_cornell();
    throw Error(spec + ": unknown builtin scene (builtins: " + builtin_list() + ")");
  }
  if (ends_with(spec, ".gltf") || ends_with(spec, ".glb")) return load_gltf(spec);
  if (ends_with(spec, ".json")) return load_manifest(spec);
  if (ends_with(spec, ".obj")) return load_obj_file(spec);
  if (ends_with(spec, ".ply")) return load_ply_file(spec);
  if (ends_with(spec, ".pbrt")) return load_pbrt(spec);
  const std::filesystem::path p(spec);
  if (!spec.empty() && !p.has_parent_path() && !p.has_extension()) {
    const std::filesystem::path manifest =
        std::filesystem::path(HRPP_SCENES_DIR) / (spec + ".scene.json");
    std::error_code ec;
    if (std::filesystem::exists(manifest, ec)) return load_manifest(manifest);
    if (const auto pbrt = fetched_pbrt(spec)) return load_pbrt(*pbrt);
    throw Error(spec + ": unknown scene: not a builtin (" + builtin_list() +
                "), a .gltf/.glb/.obj/.ply/.pbrt/.scene.json file, a manifest in " +
                HRPP_SCENES_DIR + " (available: " + manifest_list() +
                ") or a scene that tools/fetch-scenes.sh fetched (killeroo-simple, killeroo-gold)");
  }
  throw Error(spec + ": unknown scene file type (expected .gltf, .glb, .obj, .ply, .pbrt or "
              ".scene.json)");
}

void add_default_camera(Scene& scene) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const Triangle& t : scene.triangles) {
    for (const glm::vec3& v : {t.v0, t.v1, t.v2}) {
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) continue;
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  }
  if (!(lo.x <= hi.x)) lo = hi = glm::vec3(0.0f);
  const glm::vec3 centre = 0.5f * (lo + hi);
  const glm::vec3 half = 0.5f * (hi - lo);
  Camera cam;
  cam.name = "default";
  cam.yfov = glm::radians(40.0f);
  // Distance at which the box's front face (half-extent max(x, y)) fits the vertical field of
  // view (also the horizontal one for aspect >= 1), with a 10% margin.
  const float fit = std::max(half.x, half.y) / std::tan(0.5f * cam.yfov) * 1.1f;
  float distance = half.z + fit;
  if (!(distance > 0.0f)) distance = 1.0f;
  cam.position = centre + glm::vec3(0.0f, 0.0f, distance);
  cam.forward = glm::vec3(0, 0, -1);
  cam.up = glm::vec3(0, 1, 0);
  scene.cameras.insert(scene.cameras.begin(), cam);
  scene.default_camera = true;
}

}  // namespace

Scene load_scene(const std::string& spec) {
  Scene scene = dispatch(spec);
  if (scene.triangles.empty()) throw Error(spec + ": scene has no triangles");
  if (std::all_of(scene.triangles.begin(), scene.triangles.end(), is_degenerate)) {
    throw Error(spec + ": scene has no triangles with a non-zero area (all " +
                std::to_string(scene.triangles.size()) + " are degenerate)");
  }
  if (scene.cameras.empty()) add_default_camera(scene);
  return scene;
}

bool is_degenerate(const Triangle& t) {
  for (const glm::vec3& v : {t.v0, t.v1, t.v2}) {
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return true;
  }
  const glm::vec3 c = glm::cross(t.v1 - t.v0, t.v2 - t.v0);
  if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) return true;
  return c.x == 0.0f && c.y == 0.0f && c.z == 0.0f;
}

}  // namespace hrpp
