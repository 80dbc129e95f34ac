// libFuzzer target: OBJ and PLY through hrpp's code around the libraries (obj_file.cpp,
// ply_file.cpp, ply_check.cpp, polygon.cpp, mtl_material.cpp, scene_builder.cpp), through
// load_scene(). The first byte picks the format (even: .ply, odd: .obj), the rest is the file;
// an .obj's directory holds a small MTL file, m.mtl. tinyobjloader and assimp are Debian's
// libraries, not instrumented: a crash inside them is still a finding (a file hrpp hands them
// that they cannot read), but their code coverage does not guide the fuzzer. The only
// acceptable outcomes are a Scene or an hrpp::Error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.h"
#include "fuzz_input_file.h"
#include "scene/load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static bool mtl = false;
  if (!mtl) {
    const std::string m = "newmtl a\nKd 0.5 0.2 0.1\nKe 1 1 1\nNs 50\nnewmtl g\nNi 1.4\nillum 7\n";
    hrpp::fuzz::write_input("m.mtl", reinterpret_cast<const std::uint8_t*>(m.data()), m.size());
    mtl = true;
  }
  const auto file = hrpp::fuzz::write_input((data[0] & 1) ? "input.obj" : "input.ply", data + 1,
                                            size - 1);
  try {
    const hrpp::Scene scene = hrpp::load_scene(file.string());
    if (scene.shading.size() != scene.triangles.size() || scene.cameras.empty()) __builtin_trap();
  } catch (const hrpp::Error&) {
  }
  return 0;
}
