// A scene as the renderer sees it: world-space triangles in triangle-id order (docs/FORMATS.md),
// their shading data, materials, textures, lights and cameras. Loaders (glTF, manifest, built-in)
// produce it; the BVH and the GPU upload consume it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "common/name_table.h"

namespace hrpp {

// World-space triangle. Its index in Scene::triangles is its triangle id.
struct Triangle {
  glm::vec3 v0, v1, v2;
};

// A vertex colour as 0xBBGGRR (8 bits a channel, linear); kNoVertexColor (white): none.
inline constexpr std::uint32_t kNoVertexColor = 0xFFFFFFu;

// Per-triangle shading data, parallel to Scene::triangles.
struct TriangleShading {
  glm::vec3 n0{0}, n1{0}, n2{0};  // world-space vertex normals; all zero when the mesh has none
  glm::vec2 uv0{0}, uv1{0}, uv2{0};
  // Vertex colours (glTF COLOR_0), which multiply the material's base colour.
  std::uint32_t c0 = kNoVertexColor, c1 = kNoVertexColor, c2 = kNoVertexColor;
  std::uint32_t material = 0;     // index into Scene::materials
};

// One material model for every source: glTF metallic-roughness (its Appendix B BRDF) plus
// transmission and emission. Manifest overrides set it as: diffuse (metallic 0, no specular
// layer), metal (metallic 1), glass (transmission 1).
struct Material {
  std::string name;
  glm::vec3 base_color{0.8f};
  int base_color_texture = -1;  // index into Scene::textures, -1: none
  float metallic = 0.0f;
  float roughness = 1.0f;
  // glTF's metallicRoughnessTexture (linear: B scales metallic, G roughness) and
  // emissiveTexture (sRGB: it scales emission); indices into Scene::textures, -1: none.
  int metallic_roughness_texture = -1;
  int emissive_texture = -1;
  float transmission = 0.0f;    // 1: dielectric (glass)
  float ior = 1.5f;
  // The dielectric's specular layer, KHR_materials_specular's specularFactor and
  // specularColorFactor: GGX over the diffuse, Fresnel-mixed. glTF's default is 1 (the glTF
  // loader sets it); 0 here: none, the Lambertian diffuse of pbrt's diffuse, OBJ, PLY, manifests.
  float specular = 0.0f;
  glm::vec3 specular_color{1.0f};
  glm::vec3 emission{0.0f};     // emissive factor × KHR_materials_emissive_strength
  // false: only the front emits (pbrt's area lights unless "twosided"), the side that
  // cross(v1 - v0, v2 - v0) points to; glTF and manifests emit from both sides.
  bool two_sided_emission = true;
};

// Decoded texture, 8-bit RGBA, rows top to bottom as glTF stores them.
struct Texture {
  std::string name;
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;
};

enum class LightType { kPoint, kSpot, kDirectional, kAreaQuad, kEnvironment };
inline constexpr NameTable<LightType, 5> kLightTypeNames = {
    {{LightType::kPoint, "point"},
     {LightType::kSpot, "spot"},
     {LightType::kDirectional, "directional"},
     {LightType::kAreaQuad, "area"},
     {LightType::kEnvironment, "environment"}}};

struct Light {
  LightType type = LightType::kPoint;
  glm::vec3 color{1.0f};          // colour × intensity (point/spot: W/sr-ish intensity;
                                  // directional: irradiance; area/environment: radiance)
  glm::vec3 position{0.0f};       // point, spot; area: corner
  glm::vec3 direction{0, 0, -1};  // spot, directional: the direction light travels
  glm::vec3 edge_u{0.0f}, edge_v{0.0f};  // area quad: corner + s·edge_u + t·edge_v
  float inner_cone = 0.0f, outer_cone = 0.7853982f;  // spot, radians
  float range = 0.0f;             // 0: infinite
};

struct Camera {
  std::string name;
  glm::vec3 position{0.0f};
  glm::vec3 forward{0, 0, -1};  // unit
  glm::vec3 up{0, 1, 0};        // unit, orthogonal to forward
  float yfov = 0.6911504f;      // vertical field of view, radians
  float aspect = 0.0f;          // 0: take it from the image size
  // The image's right is cross(up, forward) instead of cross(forward, up): a left-handed
  // camera space (pbrt's).
  bool mirrored = false;
};

struct Scene {
  std::string name;                       // file name or builtin:NAME
  std::vector<Triangle> triangles;        // index = triangle id
  std::vector<TriangleShading> shading;   // parallel to triangles
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Light> lights;
  std::vector<Camera> cameras;            // never empty after load_scene (a default is added)
  bool default_camera = false;            // true when cameras[0] was made from the bounds
  std::vector<std::string> warnings;      // one line each, naming the file (already printed)
  // The scene file's own image settings (pbrt's Film and Sampler), the defaults of --size and
  // --spp; 0: none given.
  std::uint32_t film_width = 0, film_height = 0, film_spp = 0;
};

}  // namespace hrpp
