// A Wavefront MTL material (as assimp reads it) mapped onto hrpp's Material. The mapping is
// docs/FORMATS.md's table in "OBJ and PLY"; it is approximate where hrpp's lobes are (a
// non-metal's Ks has no specular layer to go to yet).
#pragma once

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace hrpp {

struct MtlValues {
  std::string name;
  glm::vec3 kd{0.8f};  // diffuse colour
  glm::vec3 ks{0.0f};  // specular colour
  glm::vec3 ke{0.0f};  // emission
  float ns = 0.0f;     // Phong exponent
  float d = 1.0f;      // dissolve (opacity); Tr = 1 - d
  float ni = 1.5f;     // index of refraction
  int illum = 2;       // illumination model, -1: not given
};

// The Material, and one warning line (or none) for what it cannot represent.
Material material_from_mtl(const MtlValues& mtl, std::vector<std::string>& warnings);

// GGX roughness (hrpp's, alpha = roughness²) for a Phong exponent: Walter et al. 2007's
// Beckmann match alpha = sqrt(2 / (Ns + 2)), so Ns 0 is rough (1) and Ns 1000 smooth (0.21).
float roughness_from_phong(float ns);

}  // namespace hrpp
