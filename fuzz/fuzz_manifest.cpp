// libFuzzer target: the scene-manifest parser (host/scene/manifest.cpp) on arbitrary bytes,
// through load_scene() (so the checks every scene gets run too). The manifest's directory holds
// one small valid glTF, tri.glb, so inputs that name it reach the placement and material code.
// The only acceptable outcomes are a Scene or an hrpp::Error.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/error.h"
#include "fuzz_input_file.h"
#include "scene/load_scene.h"

namespace {

// A minimal GLB: one triangle, positions only (the same bytes as corpus/manifest's tri.glb).
void write_mesh() {
  static bool done = false;
  if (done) return;
  done = true;
  const char json[] =
      "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
      "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
      "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],"
      "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"buffers\":[{\"byteLength\":36}]}";
  std::vector<std::uint8_t> j(json, json + sizeof(json) - 1);
  while (j.size() % 4) j.push_back(' ');
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::vector<std::uint8_t> glb;
  auto u32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) glb.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  const auto total = static_cast<std::uint32_t>(12 + 8 + j.size() + 8 + sizeof(pos));
  u32(0x46546C67);  // "glTF"
  u32(2);
  u32(total);
  u32(static_cast<std::uint32_t>(j.size()));
  u32(0x4E4F534A);  // "JSON"
  glb.insert(glb.end(), j.begin(), j.end());
  u32(sizeof(pos));
  u32(0x004E4942);  // "BIN\0"
  const auto* p = reinterpret_cast<const std::uint8_t*>(pos);
  glb.insert(glb.end(), p, p + sizeof(pos));
  hrpp::fuzz::write_input("tri.glb", glb.data(), glb.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  write_mesh();
  const auto file = hrpp::fuzz::write_input("input.scene.json", data, size);
  try {
    const hrpp::Scene scene = hrpp::load_scene(file.string());
    if (scene.shading.size() != scene.triangles.size() || scene.cameras.empty()) __builtin_trap();
  } catch (const hrpp::Error&) {
  }
  return 0;
}
