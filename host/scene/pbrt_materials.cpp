// pbrt-v4 materials, textures and lights onto hrpp's (pbrt_materials.h). pbrt-v4's semantics
// are read from its source: materials.cpp (parameters and defaults), lights.cpp (scale, power),
// textures.cpp (imagemap, scale), util/spectrum.cpp (the named spectra).
#include "scene/pbrt_materials.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "scene/texture_decode.h"

namespace hrpp {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct NamedMetal {
  const char* name;  // pbrt-v4's "metal-<name>-eta" and "metal-<name>-k"
  glm::vec3 eta, k;  // at about 630, 532 and 465 nm (the sRGB primaries' dominant wavelengths)
};

// Approximate optical constants at three wavelengths (after Johnson and Christy 1972 for Au, Ag
// and Cu, Rakic 1995 for Al, the measurements behind pbrt-v4's named spectra): an RGB stand-in
// for the spectral curves, good to a few percent of reflectance, not pbrt's spectral result.
constexpr NamedMetal kMetals[] = {
    {"Au", {0.18f, 0.42f, 1.37f}, {3.42f, 2.35f, 1.77f}},
    {"Ag", {0.059f, 0.059f, 0.047f}, {4.28f, 3.51f, 2.88f}},
    {"Cu", {0.27f, 1.12f, 1.17f}, {3.41f, 2.59f, 2.40f}},
    {"Al", {1.50f, 0.93f, 0.64f}, {7.64f, 6.42f, 5.54f}},
};

struct NamedGlass {
  const char* name;
  float eta;  // at 550 nm
};
constexpr NamedGlass kGlasses[] = {{"glass-BK7", 1.5168f},   {"glass-BAF10", 1.6700f},
                                   {"glass-FK51A", 1.4866f}, {"glass-LASF9", 1.8503f},
                                   {"glass-F5", 1.6034f},    {"glass-F10", 1.6200f},
                                   {"glass-F11", 1.6210f}};

float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// A spectrum parameter as RGB: an rgb, blackbody or float value, or a named metal's eta or k.
std::optional<glm::vec3> spectrum(const PbrtParams& p, const std::string& name, bool eta,
                                  PbrtWarnings& w) {
  if (auto c = p.get_rgb(name)) return c;
  const std::optional<std::string> named = p.get_spectrum_name(name);
  if (!named) return std::nullopt;
  for (const NamedMetal& m : kMetals) {
    const std::string base = std::string("metal-") + m.name + "-";
    if (*named == base + "eta" || *named == base + "k") return *named == base + "eta" ? m.eta : m.k;
  }
  for (const NamedGlass& g : kGlasses) {
    if (*named == g.name) return glm::vec3(g.eta);
  }
  w.add(p.where() + "spectrum \"" + *named + "\" for \"" + name +
        "\" is not one hrpp knows: " + (eta ? "gold's" : "a grey") + " stand-in used");
  return eta ? kMetals[0].eta : glm::vec3(0.5f);
}

void reflectance(Material& m, std::optional<PbrtTexture>& tex, const PbrtParams& p,
                 const PbrtMaterialContext& ctx, glm::vec3 fallback) {
  m.base_color = fallback;
  if (auto t = p.get_texture("reflectance")) {
    auto it = ctx.textures.find(*t);
    if (it == ctx.textures.end()) {
      throw Error(p.where() + "texture \"" + *t + "\" is not defined");
    }
    m.base_color = it->second.factor;
    if (it->second.texture >= 0) {
      m.base_color_texture = it->second.texture;
      tex = it->second;
    }
  } else if (auto c = spectrum(p, "reflectance", false, ctx.warnings)) {
    m.base_color = *c;
  }
  m.base_color = glm::clamp(m.base_color, 0.0f, 1.0f);
}

float roughness_of(const PbrtParams& p, float fallback, PbrtWarnings& w) {
  const float r = p.get_float("roughness", fallback);
  const float u = p.get_float("uroughness", r), v = p.get_float("vroughness", r);
  if (u != v) w.add(p.where() + "anisotropic roughness (uroughness != vroughness) as its mean");
  return hrpp_roughness(0.5f * (u + v), p.get_bool("remaproughness", true));
}

void conductor(PbrtMaterial& out, const PbrtParams& p, const PbrtMaterialContext& ctx) {
  Material& m = out.material;
  m.metallic = 1.0f;
  m.roughness = roughness_of(p, 0.0f, ctx.warnings);
  if (p.has("reflectance")) {
    reflectance(m, out.texture, p, ctx, glm::vec3(1.0f));
    return;
  }
  const glm::vec3 eta = spectrum(p, "eta", true, ctx.warnings).value_or(kMetals[2].eta);
  const glm::vec3 k = spectrum(p, "k", false, ctx.warnings).value_or(kMetals[2].k);
  m.base_color = conductor_f0(eta, k);  // pbrt-v4's default conductor is copper
}

// A dielectric interface's index of refraction: `eta` (its green channel), 1.5 when absent.
float ior_of(const PbrtParams& p, const PbrtMaterialContext& ctx, const std::string& type) {
  const std::optional<glm::vec3> eta = spectrum(p, "eta", false, ctx.warnings);
  const float ior = eta ? eta->y : 1.5f;
  if (!(ior > 0.0f)) throw Error(p.where() + type + " eta must be positive");
  return ior;
}

// coateddiffuse's coat (its interface's roughness and eta) as the dielectric's specular layer
// over the diffuse: glTF's Appendix B, which has no scattering between coat and base (pbrt's
// thickness, albedo and g).
void coat(Material& m, const PbrtParams& p, const PbrtMaterialContext& ctx) {
  m.specular = 1.0f;
  m.roughness = roughness_of(p, 0.0f, ctx.warnings);
  m.ior = ior_of(p, ctx, "coateddiffuse");
  ctx.warnings.add(p.where() +
                   "coateddiffuse approximated as a specular layer over the diffuse (no "
                   "scattering between them)");
}

void dielectric(PbrtMaterial& out, const std::string& type, const PbrtParams& p,
                const PbrtMaterialContext& ctx) {
  Material& m = out.material;
  m.transmission = 1.0f;
  m.base_color = glm::vec3(1.0f);
  m.ior = ior_of(p, ctx, "dielectric");
  if (type == "thindielectric") {
    ctx.warnings.add(p.where() + "thindielectric approximated as a smooth dielectric");
  } else if (roughness_of(p, 0.0f, ctx.warnings) > 0.0f) {
    ctx.warnings.add(p.where() + "rough dielectric approximated as a smooth one");
  }
}

}  // namespace

void PbrtWarnings::add(const std::string& line) {
  if (std::find(lines_.begin(), lines_.end(), line) == lines_.end()) lines_.push_back(line);
}

float hrpp_roughness(float pbrt_roughness, bool remap) {
  const float r = std::clamp(pbrt_roughness, 0.0f, 1.0f);
  const float alpha = remap ? std::sqrt(r) : r;  // TrowbridgeReitzDistribution::RoughnessToAlpha
  return std::sqrt(alpha);
}

glm::vec3 conductor_f0(const glm::vec3& eta, const glm::vec3& k) {
  const glm::vec3 a = (eta - 1.0f) * (eta - 1.0f) + k * k;
  const glm::vec3 b = (eta + 1.0f) * (eta + 1.0f) + k * k;
  return glm::clamp(a / b, 0.0f, 1.0f);
}

PbrtMaterial pbrt_material(const std::string& type, const PbrtParams& p,
                           const PbrtMaterialContext& ctx) {
  PbrtMaterial out;
  out.material.name = type;
  if (type == "diffuse" || type == "coateddiffuse" || type == "diffusetransmission") {
    reflectance(out.material, out.texture, p, ctx, glm::vec3(0.5f));
    if (type == "coateddiffuse") {
      coat(out.material, p, ctx);
    } else if (type != "diffuse") {
      ctx.warnings.add(p.where() + "diffusetransmission approximated as diffuse (its "
                                   "transmission is left out)");
    }
  } else if (type == "conductor" || type == "coatedconductor") {
    conductor(out, p, ctx);
    if (type != "conductor") {
      ctx.warnings.add(p.where() + "coatedconductor approximated as a conductor (no coat)");
    }
  } else if (type == "dielectric" || type == "thindielectric") {
    dielectric(out, type, p, ctx);
  } else if (type == "interface" || type == "none" || type == "") {
    ctx.warnings.add(p.where() + "material \"" + type + "\" (no surface) rendered as diffuse");
  } else {
    ctx.warnings.add(p.where() + "material \"" + type + "\" is not supported: diffuse 0.5 used");
  }
  return out;
}

PbrtTexture pbrt_texture(const std::string& cls, const PbrtParams& p,
                         const std::map<std::string, PbrtTexture>& textures,
                         const std::string& image_file, Scene& scene, PbrtWarnings& w) {
  PbrtTexture t;
  if (cls == "imagemap") {
    scene.textures.push_back(read_texture_file(image_file, p.where() + "imagemap"));
    t.texture = static_cast<int>(scene.textures.size() - 1);
    t.factor = glm::vec3(p.get_float("scale", 1.0f));
    t.uv_scale = glm::vec2(p.get_float("uscale", 1.0f), p.get_float("vscale", 1.0f));
    t.uv_offset = glm::vec2(p.get_float("udelta", 0.0f), p.get_float("vdelta", 0.0f));
    if (p.get_bool("invert", false)) w.add(p.where() + "imagemap \"invert\" is ignored");
  } else if (cls == "scale") {
    if (auto name = p.get_texture("tex")) {
      auto it = textures.find(*name);
      if (it == textures.end()) throw Error(p.where() + "texture \"" + *name + "\" is not defined");
      t = it->second;
    } else if (auto c = p.get_rgb("tex")) {
      t.factor = *c;
    }
    t.factor *= p.get_float("scale", 1.0f);
  } else if (cls == "constant") {
    t.factor = p.get_rgb("value").value_or(glm::vec3(1.0f));
  } else {
    w.add(p.where() + "texture class \"" + cls + "\" is not supported: a constant 0.5 used");
    t.factor = glm::vec3(0.5f);
  }
  return t;
}

namespace {

glm::vec3 scaled(const PbrtParams& p, const char* name, glm::vec3 fallback) {
  return p.get_rgb(name).value_or(fallback) * p.get_float("scale", 1.0f);
}

glm::vec3 at(const glm::dmat4& m, const glm::vec3& p) {
  return glm::vec3(m * glm::dvec4(glm::dvec3(p), 1.0));
}

glm::vec3 direction(const glm::dmat4& m, const glm::vec3& from, const glm::vec3& to) {
  return glm::normalize(at(m, to) - at(m, from));
}

}  // namespace

std::optional<Light> pbrt_light(const std::string& type, const PbrtParams& p, const glm::dmat4& m,
                                PbrtWarnings& w) {
  Light l;
  const glm::vec3 from = p.get_point3s("from").empty() ? glm::vec3(0) : p.get_point3s("from")[0];
  const glm::vec3 to = p.get_point3s("to").empty() ? glm::vec3(0, 0, 1) : p.get_point3s("to")[0];
  if (type == "point" || type == "spot") {
    l.type = type == "point" ? LightType::kPoint : LightType::kSpot;
    l.position = at(m, from);
    l.color = scaled(p, "I", glm::vec3(1.0f));
    const float cone = glm::radians(p.get_float("coneangle", 30.0f));
    const float delta = glm::radians(p.get_float("conedelta", 5.0f));
    const float power = p.get_float("power", -1.0f);
    if (type == "spot") {
      l.direction = direction(m, from, to);
      l.outer_cone = cone;
      l.inner_cone = std::max(0.0f, cone - delta);
    }
    if (power > 0.0f && luminance(l.color) > 0.0f) {  // pbrt-v4: I normalised, then power / 4π
      const double solid =
          type == "point"
              ? 4.0 * kPi
              : 2.0 * kPi * (1.0 - 0.5 * (std::cos(l.inner_cone) + std::cos(l.outer_cone)));
      l.color *= static_cast<float>(power / solid) / luminance(l.color);
    }
  } else if (type == "distant") {
    l.type = LightType::kDirectional;
    l.direction = direction(m, from, to);
    l.color = scaled(p, "L", glm::vec3(1.0f));
    const float e = p.get_float("illuminance", -1.0f);
    if (e > 0.0f && luminance(l.color) > 0.0f) l.color *= e / luminance(l.color);
  } else if (type == "infinite") {
    l.type = LightType::kEnvironment;
    l.color = scaled(p, "L", glm::vec3(1.0f));
    if (p.has("filename")) {
      w.add(p.where() +
            "infinite light with an image (\"filename\") is not supported yet: "
            "left out");
      p.get_string("filename", "");
      return std::nullopt;
    }
    const float e = p.get_float("illuminance", -1.0f);
    if (e > 0.0f && luminance(l.color) > 0.0f) {
      l.color *= e / (static_cast<float>(kPi) * luminance(l.color));
    }
  } else {
    w.add(p.where() + "light \"" + type + "\" is not supported: left out");
    return std::nullopt;
  }
  return l;
}

}  // namespace hrpp
