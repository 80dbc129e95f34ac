// libFuzzer target: the glTF loader (host/scene/gltf_loader.cpp, through tinygltf) on arbitrary
// bytes. An input starting with the GLB magic is loaded as .glb, anything else as .gltf. The
// only acceptable outcomes are a Scene or an hrpp::Error; a crash, a sanitizer report, a hang or
// an escaping exception of another type is a finding.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "common/error.h"
#include "fuzz_input_file.h"
#include "scene/load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const auto file = hrpp::fuzz::write_input(glb ? "input.glb" : "input.gltf", data, size);
  try {
    const hrpp::Scene scene = hrpp::load_gltf(file);
    // Every loaded triangle has a material; shading is parallel to triangles.
    if (scene.shading.size() != scene.triangles.size()) __builtin_trap();
    for (const hrpp::TriangleShading& s : scene.shading)
      if (s.material >= scene.materials.size()) __builtin_trap();
  } catch (const hrpp::Error&) {
  }
  return 0;
}
