#include "scene/gltf_topology.h"

#include <cstddef>

namespace hrpp {

const char* gltf_mode_name(int mode) {
  static const char* const kNames[] = {"POINTS",    "LINES",          "LINE_LOOP",   "LINE_STRIP",
                                       "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};
  return mode >= 0 && mode <= 6 ? kNames[mode] : "unknown";
}

std::vector<std::uint32_t> triangle_list(int mode, std::vector<std::uint32_t> sequence) {
  if (mode == kGltfTriangles) return sequence;
  const std::size_t n = sequence.size();
  const std::size_t triangles = n < 3 ? 0 : n - 2;
  std::vector<std::uint32_t> out;
  out.reserve(3 * triangles);
  for (std::size_t i = 0; i < triangles; ++i) {
    if (mode == kGltfTriangleStrip) {
      out.insert(out.end(), {sequence[i], sequence[i + 1 + i % 2], sequence[i + 2 - i % 2]});
    } else {
      out.insert(out.end(), {sequence[i + 1], sequence[i + 2], sequence[0]});
    }
  }
  return out;
}

}  // namespace hrpp
