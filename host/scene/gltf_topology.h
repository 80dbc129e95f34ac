// glTF primitive topologies (glTF 2.0 spec, 3.7.2.1): which modes are surfaces, and triangle
// strips and fans expanded into triangle lists with the spec's vertex order (and so winding).
#pragma once

#include <cstdint>
#include <vector>

namespace hrpp {

inline constexpr int kGltfTriangles = 4, kGltfTriangleStrip = 5, kGltfTriangleFan = 6;

// POINTS (0), LINES (1), LINE_LOOP (2), LINE_STRIP (3): valid glTF, no surface to render.
inline bool is_point_or_line_mode(int mode) { return mode >= 0 && mode <= 3; }

// Name of a primitive mode for messages ("TRIANGLE_FAN"; "unknown" outside 0..6).
const char* gltf_mode_name(int mode);

// The triangle list (3 indices a triangle) of a TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN
// primitive whose vertex sequence is `sequence` (its indices, or 0..n-1 without indices):
//   TRIANGLES: the sequence itself (its size must be a multiple of 3, the caller checks);
//   TRIANGLE_STRIP: triangle i = {v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]}, i < n - 2;
//   TRIANGLE_FAN:   triangle i = {v[i + 1], v[i + 2], v[0]},              i < n - 2.
// Fewer than 3 vertices make no strip or fan triangle.
std::vector<std::uint32_t> triangle_list(int mode, std::vector<std::uint32_t> sequence);

}  // namespace hrpp
