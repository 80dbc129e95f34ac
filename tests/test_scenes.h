// Scenes the BVH and traversal suites run on: the built-in Cornell box and the committed meshes.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/bvh.h"
#include "scene/load_scene.h"
#include "trace/ray_batches.h"

namespace hrpp::test {

inline std::vector<std::string> reference_scene_names() {
  return {"builtin:cornell", "meshes/cornell_box.glb", "meshes/utah_teapot.glb",
          "meshes/mcguire_bunny.glb"};
}

// Loads a name from reference_scene_names(); mesh paths are relative to the source scenes/.
inline Scene load_test_scene(const std::string& name) {
  if (name.rfind("builtin:", 0) == 0) return load_scene(name);
  return load_scene((std::filesystem::path(HRPP_TEST_SCENES_DIR) / name).string());
}

// A scene of the given triangles alone: one default material, default shading.
inline Scene synthetic_scene(std::vector<Triangle> tris) {
  Scene s;
  s.name = "synthetic";
  s.triangles = std::move(tris);
  s.shading.resize(s.triangles.size());
  s.materials.resize(1);
  return s;
}

// The BVH configuration with spatial splits (SBVH); the rest as BvhConfig's defaults.
inline BvhConfig spatial_splits() {
  BvhConfig c;
  c.splits = BvhSplits::kSpatial;
  return c;
}

// The Aila–Laine batches at test size: side × side primary rays and `secondary` AO and diffuse
// rays, on one thread (the same rays on every machine).
inline RayBatches small_ray_batches(const Scene& scene, const GpuBvh& bvh, std::uint32_t side,
                                    std::size_t secondary) {
  RayBatchConfig c;
  c.width = c.height = side;
  c.secondary_count = secondary;
  c.threads = 1;
  return make_ray_batches(scene, bvh, c);
}

// Test-name-safe form of a scene name for INSTANTIATE_TEST_SUITE_P.
inline std::string scene_param_name(const testing::TestParamInfo<std::string>& info) {
  std::string s = std::filesystem::path(info.param).stem().string();
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

}  // namespace hrpp::test
