// libFuzzer target: the pbrt-v4 reader (host/scene/pbrt_loader.cpp: tokenizer, parameter lists,
// directives, shapes, Loop subdivision, materials and lights) on arbitrary bytes, through
// load_scene(). The input's directory holds a small valid PLY, tri.ply, and an include file,
// inc.pbrt, so inputs that name them reach plymesh and Include. The only acceptable outcomes are
// a Scene or an hrpp::Error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.h"
#include "fuzz_input_file.h"
#include "scene/load_scene.h"

namespace {

void write_neighbours() {
  static bool done = false;
  if (done) return;
  done = true;
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  hrpp::fuzz::write_input("tri.ply", reinterpret_cast<const std::uint8_t*>(ply.data()), ply.size());
  const std::string inc = "Translate 1 2 3\nShape \"sphere\" \"float radius\" 0.5\n";
  hrpp::fuzz::write_input("inc.pbrt", reinterpret_cast<const std::uint8_t*>(inc.data()),
                          inc.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  write_neighbours();
  const auto file = hrpp::fuzz::write_input("input.pbrt", data, size);
  try {
    const hrpp::Scene scene = hrpp::load_scene(file.string());
    if (scene.shading.size() != scene.triangles.size() || scene.cameras.empty()) __builtin_trap();
  } catch (const hrpp::Error&) {
  }
  return 0;
}
