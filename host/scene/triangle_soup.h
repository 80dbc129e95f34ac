// A generated scene for size limits: `count` small random triangles (about 0.1 units across) in
// a 100-unit box, one default material, no lights or cameras (bench_big_scene, the device-memory
// tests). The same seed gives the same scene.
#pragma once

#include <cstddef>
#include <cstdint>

#include "scene/scene.h"

namespace hrpp {

Scene make_triangle_soup(std::size_t count, std::uint32_t seed);

}  // namespace hrpp
