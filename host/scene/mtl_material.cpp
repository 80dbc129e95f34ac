// material_from_mtl(): the MTL-to-Material table of docs/FORMATS.md.
#include "scene/mtl_material.h"

#include <algorithm>
#include <cmath>

namespace hrpp {
namespace {

float max3(const glm::vec3& c) { return std::max(c.x, std::max(c.y, c.z)); }

bool is_glass_model(int illum) { return illum == 4 || illum == 6 || illum == 7 || illum == 9; }

}  // namespace

float roughness_from_phong(float ns) {
  const float alpha = std::sqrt(2.0f / (std::max(ns, 0.0f) + 2.0f));
  return std::clamp(std::sqrt(alpha), 0.0f, 1.0f);
}

Material material_from_mtl(const MtlValues& mtl, std::vector<std::string>& warnings) {
  Material m;
  m.name = mtl.name;
  m.base_color = glm::clamp(mtl.kd, 0.0f, 1.0f);
  m.emission = glm::max(mtl.ke, glm::vec3(0.0f));
  m.roughness = roughness_from_phong(mtl.ns);
  if (is_glass_model(mtl.illum)) {
    m.transmission = 1.0f;
    m.ior = mtl.ni > 0.0f ? mtl.ni : 1.5f;
    m.base_color = glm::vec3(1.0f);
    return m;
  }
  // A surface whose specular colour outweighs its diffuse one is a metal of that colour
  // (illum 3, "reflection on", likewise); a non-metal's Ks awaits a specular layer.
  if (max3(mtl.ks) > max3(mtl.kd) || (mtl.illum == 3 && max3(mtl.ks) > 0.0f)) {
    m.metallic = 1.0f;
    m.base_color = glm::clamp(mtl.ks, 0.0f, 1.0f);
  }
  if (mtl.d < 1.0f) {
    warnings.push_back("material '" + mtl.name + "': dissolve d = " + std::to_string(mtl.d) +
                       " is rendered opaque (no alpha yet)");
  }
  return m;
}

}  // namespace hrpp
