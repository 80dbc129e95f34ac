#include "scene/triangle_soup.h"

#include <random>

namespace hrpp {

Scene make_triangle_soup(std::size_t count, std::uint32_t seed) {
  Scene scene;
  scene.name = "soup";
  scene.materials.emplace_back();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(0.0f, 100.0f), off(-0.05f, 0.05f);
  const auto corner = [&](const glm::vec3& c) {
    return c + glm::vec3(off(rng), off(rng), off(rng));
  };
  scene.triangles.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const glm::vec3 c(pos(rng), pos(rng), pos(rng));
    const glm::vec3 v0 = corner(c), v1 = corner(c), v2 = corner(c);
    scene.triangles.push_back({v0, v1, v2});
  }
  scene.shading.resize(count);
  return scene;
}

}  // namespace hrpp
