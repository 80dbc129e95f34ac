// pbrt-v4's materials, textures and lights mapped onto hrpp's (docs/FORMATS.md, "pbrt-v4"): the
// nearest of hrpp's lobes, with one warning line for each approximation or unsupported feature.
#pragma once

#include <glm/glm.hpp>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scene/pbrt_params.h"
#include "scene/scene.h"

namespace hrpp {

// A pbrt texture as hrpp can use it: an image (Scene::textures index) times a factor, read
// through pbrt's uv mapping s = su u + du, t = sv v + dv; or a constant (texture -1).
struct PbrtTexture {
  int texture = -1;
  glm::vec3 factor{1.0f};
  glm::vec2 uv_scale{1.0f}, uv_offset{0.0f};
};

// Warnings are collected once per distinct line (the loader prints them).
class PbrtWarnings {
 public:
  void add(const std::string& line);
  const std::vector<std::string>& lines() const { return lines_; }

 private:
  std::vector<std::string> lines_;
};

struct PbrtMaterialContext {
  const std::map<std::string, PbrtTexture>& textures;
  PbrtWarnings& warnings;
};

// The Material for `Material "type" params` (or MakeNamedMaterial's "string type"), and the
// texture its reflectance reads, if any (its uv mapping is applied to the meshes that use it).
struct PbrtMaterial {
  Material material;
  std::optional<PbrtTexture> texture;
};
PbrtMaterial pbrt_material(const std::string& type, const PbrtParams& params,
                           const PbrtMaterialContext& ctx);

// `Texture "name" "spectrum"|"float" "class" params`: imagemap (files resolved by `resolve`),
// scale and constant; any other class is a constant 0.5 with a warning.
PbrtTexture pbrt_texture(const std::string& cls, const PbrtParams& params,
                         const std::map<std::string, PbrtTexture>& textures,
                         const std::string& image_file, Scene& scene, PbrtWarnings& warnings);

// `LightSource "type" params` under object-to-world `m`: point, spot, distant and infinite
// (a constant radiance; an image map is warned about and left out). Nothing for other types.
std::optional<Light> pbrt_light(const std::string& type, const PbrtParams& params,
                                const glm::dmat4& m, PbrtWarnings& warnings);

// pbrt-v4's roughness (remapped or not) as hrpp's (GGX alpha = roughness²).
float hrpp_roughness(float pbrt_roughness, bool remap);

// Reflectance at normal incidence of a conductor of complex index eta + i k, per channel.
glm::vec3 conductor_f0(const glm::vec3& eta, const glm::vec3& k);

}  // namespace hrpp
