// libFuzzer target: hrpp's own code around the OBJ and PLY libraries. The first byte picks the
// format, the rest is the file. An odd first byte: an .obj through load_scene() (obj_file.cpp,
// polygon.cpp, mtl_material.cpp, scene_builder.cpp over tinyobjloader's streaming reader), its
// directory holding a small MTL file, m.mtl. An even one: a .ply through hrpp's structure check
// (ply_check.cpp), the code that stands between a file and assimp. assimp itself is not fuzzed
// here: it is Debian's library, not instrumented, and assimp 5.2 (Debian 12) crashes on
// malformed PLY files that pass the check (found by this target with assimp behind the check;
// docs/TESTING.md, "Sanitizers and fuzzing"). The only acceptable outcomes are a Scene (or a
// passed check) or an hrpp::Error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.h"
#include "fuzz_input_file.h"
#include "scene/load_scene.h"
#include "scene/ply_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static bool mtl = false;
  if (!mtl) {
    const std::string m = "newmtl a\nKd 0.5 0.2 0.1\nKe 1 1 1\nNs 50\nnewmtl g\nNi 1.4\nillum 7\n";
    hrpp::fuzz::write_input("m.mtl", reinterpret_cast<const std::uint8_t*>(m.data()), m.size());
    mtl = true;
  }
  const bool obj = (data[0] & 1) != 0;
  const auto file = hrpp::fuzz::write_input(obj ? "input.obj" : "input.ply", data + 1, size - 1);
  try {
    if (!obj) {
      hrpp::check_ply_file(file);
      return 0;
    }
    const hrpp::Scene scene = hrpp::load_scene(file.string());
    if (scene.shading.size() != scene.triangles.size() || scene.cameras.empty()) __builtin_trap();
  } catch (const hrpp::Error&) {
  }
  return 0;
}
