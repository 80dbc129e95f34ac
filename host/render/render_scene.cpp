#include "render/render_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>

#include "common/error.h"
#include "scene/load_scene.h"
#include "surface_hit.h"

namespace hrpp {

static_assert(sizeof(gpu::RenderParams) == 128);
static_assert(sizeof(gpu::PathState) == 32);
static_assert(sizeof(gpu::ShadowRecord) == 16);
static_assert(sizeof(gpu::RenderQueues) == 64);
static_assert(sizeof(gpu::RenderPushConstants) == 16);
// Read as 2, 1, 4 and 4 16-byte texels (shaders/lib/render_bindings.glsl: load_*).
static_assert(sizeof(gpu::Ray) == 32 && sizeof(gpu::Hit) == 16);
static_assert(sizeof(gpu::GpuMaterial) == 80);
static_assert(sizeof(gpu::GpuLight) == 64);
static_assert(offsetof(gpu::GpuLight, cdf) == 28);  // light_cdf(): texel 1, .w
static_assert(sizeof(gpu::GpuTexture) == 16);
static_assert(sizeof(gpu::OffsetRayCase) == 64 && sizeof(gpu::OffsetRayResult) == 48);

namespace {

constexpr float kPi = 3.14159265358979f;

float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

bool emits(const glm::vec3& e) { return e.r > 0.0f || e.g > 0.0f || e.b > 0.0f; }

// Halves a texture with a 2×2 box filter (odd sizes keep their last row/column).
Texture halve(const Texture& t) {
  Texture h;
  h.name = t.name;
  h.width = std::max(1, t.width / 2);
  h.height = std::max(1, t.height / 2);
  h.rgba.resize(static_cast<std::size_t>(h.width) * h.height * 4);
  for (int y = 0; y < h.height; ++y)
    for (int x = 0; x < h.width; ++x)
      for (int c = 0; c < 4; ++c) {
        int sum = 0;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const int sx = std::min(2 * x + dx, t.width - 1);
            const int sy = std::min(2 * y + dy, t.height - 1);
            sum += t.rgba[(static_cast<std::size_t>(sy) * t.width + sx) * 4 + c];
          }
        h.rgba[(static_cast<std::size_t>(y) * h.width + x) * 4 + c] =
            static_cast<std::uint8_t>((sum + 2) / 4);
      }
  return h;
}

void add_textures(const Scene& scene, std::size_t budget, RenderScene& out) {
  std::vector<Texture> tex = scene.textures;
  const auto bytes = [&] {
    std::size_t b = 0;
    for (const Texture& t : tex) b += static_cast<std::size_t>(t.width) * t.height * 4;
    return b;
  };
  while (bytes() > budget) {
    for (Texture& t : tex) t = halve(t);
    ++out.texture_halvings;
  }
  for (const Texture& t : tex) {
    gpu::GpuTexture g{};
    g.offset = static_cast<std::uint32_t>(out.texels.size());
    g.width = t.width;
    g.height = t.height;
    out.textures.push_back(g);
    for (std::size_t i = 0; i + 3 < t.rgba.size(); i += 4)
      out.texels.push_back(static_cast<std::uint32_t>(t.rgba[i]) |
                           static_cast<std::uint32_t>(t.rgba[i + 1]) << 8 |
                           static_cast<std::uint32_t>(t.rgba[i + 2]) << 16 |
                           static_cast<std::uint32_t>(t.rgba[i + 3]) << 24);
  }
}

}  // namespace

const char* RenderFeatures::name(int feature) {
  static const char* const kNames[HRPP_FEATURE_COUNT] = {
      "textures",    "emissive_triangles", "point_lights", "spot_lights",
      "directional_lights", "environment", "metal",        "glass",
      "specular_layer", "material_textures"};
  return kNames[feature];
}

std::vector<std::string> RenderFeatures::names_on() const {
  std::vector<std::string> n;
  for (int f = 0; f < HRPP_FEATURE_COUNT; ++f)
    if (on[f]) n.emplace_back(name(f));
  return n;
}

namespace {

// The Fresnel of a dielectric's specular layer at grazing incidence (KHR_materials_specular's
// factor, within [0, 1]) and at normal incidence: the ior's, tinted by the specular colour,
// times that factor.
float specular_f90(const Material& m) { return std::clamp(m.specular, 0.0f, 1.0f); }

glm::vec3 specular_f0(const Material& m) {
  const float r = (m.ior - 1.0f) / (m.ior + 1.0f);
  const glm::vec3 tint = glm::max(m.specular_color, glm::vec3(0.0f));
  return glm::min(r * r * tint, glm::vec3(1.0f)) * specular_f90(m);
}

// Texture `t` of the scene, -1 for none or one that does not exist.
int texture_index(const Scene& scene, int t) {
  return t >= 0 && t < static_cast<int>(scene.textures.size()) ? t : -1;
}

// The materials and the features they need (textures, metal, glass, a specular layer).
void add_materials(const Scene& scene, RenderScene& out) {
  bool& f_tex = out.features.on[HRPP_FEATURE_TEXTURES];
  bool& f_metal = out.features.on[HRPP_FEATURE_METAL];
  bool& f_glass = out.features.on[HRPP_FEATURE_GLASS];
  bool& f_specular = out.features.on[HRPP_FEATURE_SPECULAR_LAYER];
  bool& f_material_tex = out.features.on[HRPP_FEATURE_MATERIAL_TEXTURES];
  for (const Material& m : scene.materials) {
    gpu::GpuMaterial g{};
    g.base_color = m.base_color;
    const bool textured = m.base_color_texture >= 0 &&
                          m.base_color_texture < static_cast<int>(scene.textures.size());
    g.texture = textured ? m.base_color_texture : -1;
    g.metallic_roughness_texture = texture_index(scene, m.metallic_roughness_texture);
    g.emissive_texture = texture_index(scene, m.emissive_texture);
    g.emission = m.emission;
    g.metallic = m.metallic;
    g.roughness = m.roughness;
    g.transmission = m.transmission;
    g.ior = m.ior;
    g.flags = m.two_sided_emission ? 0u : HRPP_MATERIAL_ONE_SIDED;
    g.specular_f0 = specular_f0(m);
    g.specular_f90 = specular_f90(m);
    out.materials.push_back(g);
    const bool opaque = m.transmission <= 0.5f;
    f_tex = f_tex || textured;
    f_material_tex =
        f_material_tex || g.metallic_roughness_texture >= 0 || g.emissive_texture >= 0;
    f_glass = f_glass || !opaque;
    f_metal = f_metal || (opaque && m.metallic > 0.0f);
    f_specular = f_specular || (opaque && m.metallic < 1.0f && g.specular_f90 > 0.0f);
  }
}

// Whether triangle t of material m is a light (next-event estimation samples it). An emissive
// texture makes its emission vary over the triangle, which a light sample does not look up:
// such triangles are found by the paths' BSDF samples alone (emission_weight 1).
bool is_triangle_light(const Triangle& t, const gpu::GpuMaterial& m) {
  return emits(m.emission) && m.emissive_texture < 0 && !is_degenerate(t);
}

// Whether a material emits through an emissive texture (its triangles emit, but are no lights).
bool has_textured_emission(const RenderScene& rs) {
  for (const gpu::GpuMaterial& m : rs.materials)
    if (emits(m.emission) && m.emissive_texture >= 0) return true;
  return false;
}

std::uint32_t material_of(const Scene& scene, const TriangleShading& s) {
  return s.material < scene.materials.size() ? s.material : 0;
}

// A light per emissive triangle (its power into `power`); returns the radius of the scene's
// bounding sphere.
float add_triangle_lights(const Scene& scene, RenderScene& out, std::vector<float>& power) {
  glm::vec3 lo(3e38f), hi(-3e38f);
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const Triangle& t = scene.triangles[i];
    lo = glm::min(lo, glm::min(t.v0, glm::min(t.v1, t.v2)));
    hi = glm::max(hi, glm::max(t.v0, glm::max(t.v1, t.v2)));
    const gpu::GpuMaterial& m = out.materials[material_of(scene, scene.shading[i])];
    if (!is_triangle_light(t, m)) continue;
    const glm::vec3 e = m.emission;
    // Flux π · L · area a side.
    const float area = 0.5f * glm::length(glm::cross(t.v1 - t.v0, t.v2 - t.v0));
    const bool one_sided = (out.materials[material_of(scene, scene.shading[i])].flags &
                            HRPP_MATERIAL_ONE_SIDED) != 0u;
    gpu::GpuLight l{};
    l.type = HRPP_LIGHT_TRIANGLE;
    l.position = t.v0;
    l.dir = t.v1 - t.v0;
    l.edge2 = t.v2 - t.v0;
    l.color = e;
    l.cos_inner = one_sided ? 1.0f : 0.0f;
    out.lights.push_back(l);
    power.push_back((one_sided ? 1.0f : 2.0f) * kPi * luminance(e) * area);
    ++out.emissive_triangles;
  }
  return 0.5f * glm::length(hi - lo);
}

ShadeCorner shade_corner(const glm::vec3& p, const glm::vec3& n, std::uint32_t color,
                         const glm::vec2& uv, std::uint32_t light) {
  ShadeCorner c{};
  c.vertex.position = p;
  c.vertex.light = light;
  c.attributes.normal_color = glm::vec4(n, static_cast<float>(color));  // below 2^24: exact
  c.attributes.uv = glm::vec4(uv, 0.0f, 0.0f);
  return c;
}

// Whether any of the corners' attributes differs from the defaults in a byte.
bool has_attributes(const std::array<ShadeCorner, 3>& c) {
  const gpu::ShadeAttributes d = gpu::default_shade_attributes();
  for (const ShadeCorner& k : c)
    if (std::memcmp(&k.attributes, &d, sizeof(d)) != 0) return true;
  return false;
}

// HRPP_VERTEX_NORMALS | HRPP_VERTEX_COLORS: which the triangle has.
std::uint32_t vertex_data(const TriangleShading& s) {
  const bool normals =
      s.n0 != glm::vec3(0.0f) || s.n1 != glm::vec3(0.0f) || s.n2 != glm::vec3(0.0f);
  const bool colors = s.c0 != kNoVertexColor || s.c1 != kNoVertexColor || s.c2 != kNoVertexColor;
  return (normals ? HRPP_VERTEX_NORMALS : 0u) | (colors ? HRPP_VERTEX_COLORS : 0u);
}

// The indexed shading data, in two passes: the triangles with attributes, whose vertices so come
// first (IndexedShading::attributes), then the others. Emissive triangles are lights 1, 2, ...
// in triangle order (add_triangle_lights's) while the scene has lights.
void add_shading(const Scene& scene, RenderScene& out) {
  if (out.materials.size() > HRPP_SHADE_MATERIAL_MASK)
    throw Error("scene '" + scene.name + "': over 2^29 materials");
  const bool lights = !out.lights.empty();
  out.shading.triangles.resize(scene.triangles.size());
  ShadeVertexTable table(out.shading);
  for (const bool with_attributes : {true, false}) {
    std::uint32_t next_light = 1;
    for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
      const Triangle& t = scene.triangles[i];
      const TriangleShading& s = scene.shading[i];
      const std::uint32_t material = material_of(scene, s);
      const bool light = lights && is_triangle_light(t, out.materials[material]);
      const std::array<ShadeCorner, 3> c = {
          shade_corner(t.v0, s.n0, s.c0, s.uv0, light ? next_light++ : 0u),
          shade_corner(t.v1, s.n1, s.c1, s.uv1, 0u), shade_corner(t.v2, s.n2, s.c2, s.uv2, 0u)};
      if (has_attributes(c) != with_attributes) continue;
      gpu::ShadeIndex& g = out.shading.triangles[i];
      g.corner0 = table.insert(c[0], with_attributes);
      g.corner1 = table.insert(c[1], with_attributes);
      g.corner2 = table.insert(c[2], with_attributes);
      g.material_data = material | (with_attributes ? HRPP_SHADE_ATTRIBUTES : 0u) |
                        vertex_data(s) << HRPP_SHADE_DATA_SHIFT;
    }
  }
}

// Point, spot and directional lights (power into `power`) and the environment.
void add_scene_lights(const Scene& scene, float radius, RenderScene& out,
                      std::vector<float>& power) {
  for (const Light& light : scene.lights) {
    gpu::GpuLight l{};
    l.color = light.color;
    l.position = light.position;
    l.dir = glm::length(light.direction) > 0.0f ? glm::normalize(light.direction)
                                                : glm::vec3(0, 0, -1);
    l.cos_inner = std::cos(light.inner_cone);
    l.cos_outer = std::cos(light.outer_cone);
    float p = 0.0f;
    switch (light.type) {
      case LightType::kPoint:
        l.type = HRPP_LIGHT_POINT;
        p = 4.0f * kPi * luminance(light.color);
        out.features.on[HRPP_FEATURE_POINT_LIGHTS] = true;
        break;
      case LightType::kSpot:
        l.type = HRPP_LIGHT_SPOT;
        p = 2.0f * kPi * (1.0f - 0.5f * (l.cos_inner + l.cos_outer)) * luminance(light.color);
        out.features.on[HRPP_FEATURE_SPOT_LIGHTS] = true;
        break;
      case LightType::kDirectional:
        l.type = HRPP_LIGHT_DIRECTIONAL;
        p = kPi * radius * radius * luminance(light.color);
        out.features.on[HRPP_FEATURE_DIRECTIONAL_LIGHTS] = true;
        break;
      case LightType::kEnvironment:
        out.environment += light.color;
        continue;
      case LightType::kAreaQuad:
        continue;  // sampled through its emissive triangles
    }
    if (!(p > 0.0f)) continue;
    out.lights.push_back(l);
    power.push_back(p);
    ++out.delta_lights;
  }
}

// Light selection by power: each light's cdf; no light with power, no lights.
void make_light_cdf(const std::vector<float>& power, RenderScene& out) {
  double total = 0.0;
  for (float p : power) total += p;
  if (!(total > 0.0)) {
    out.lights.clear();
  } else {
    double run = 0.0;
    for (std::size_t i = 0; i < out.lights.size(); ++i) {
      run += power[i];
      out.lights[i].cdf = static_cast<float>(run / total);
    }
    out.lights.back().cdf = 1.0f;
  }
}

// A scene without light: the default environment and sun (a directional light, picked always).
void add_default_lighting(const DefaultLighting& d, RenderScene& out) {
  const bool sun = d.sun > 0.0f;
  out.lighting = emits(d.environment) || sun ? Lighting::kDefault : Lighting::kNone;
  out.environment = d.environment;
  if (!sun) return;
  gpu::GpuLight l{};
  l.type = HRPP_LIGHT_DIRECTIONAL;
  l.color = glm::vec3(d.sun);
  l.dir = glm::normalize(DefaultLighting::kSunDirection);
  l.cdf = 1.0f;
  out.lights.push_back(l);
  out.default_sun = d.sun;
  ++out.delta_lights;
  out.features.on[HRPP_FEATURE_DIRECTIONAL_LIGHTS] = true;
}

}  // namespace

RenderScene make_render_scene(const Scene& scene, const DefaultLighting& lighting,
                              std::size_t texel_budget_bytes) {
  RenderScene out;
  out.triangle_count = scene.triangles.size();
  add_materials(scene, out);
  if (out.materials.empty()) out.materials.push_back(gpu::GpuMaterial{});
  if (out.features.on[HRPP_FEATURE_TEXTURES] || out.features.on[HRPP_FEATURE_MATERIAL_TEXTURES])
    add_textures(scene, texel_budget_bytes, out);
  if (out.texels.empty()) out.texels.push_back(0);  // bindings need a non-empty buffer
  if (out.textures.empty()) out.textures.push_back(gpu::GpuTexture{});

  std::vector<float> power;
  const float radius = add_triangle_lights(scene, out, power);
  const bool textured_emission = has_textured_emission(out);
  out.features.on[HRPP_FEATURE_EMISSIVE_TRIANGLES] =
      out.emissive_triangles > 0 || textured_emission;
  add_scene_lights(scene, radius, out, power);
  make_light_cdf(power, out);
  add_shading(scene, out);  // emissive triangles are lights only while a light has power
  if (out.lights.empty() && !emits(out.environment) && !textured_emission)
    add_default_lighting(lighting, out);
  out.features.on[HRPP_FEATURE_ENVIRONMENT] = emits(out.environment);
  return out;
}

}  // namespace hrpp
