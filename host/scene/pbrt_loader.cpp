// The pbrt-v4 scene reader (pbrt_loader.h). Semantics follow pbrt-v4's own source
// (src/pbrt/parser.cpp for the directives, scene.cpp for the graphics state, shapes.cpp,
// lights.cpp, materials.cpp); the tokens and parameter lists are pbrt_tokenizer.h and
// pbrt_params.h, the shapes' triangles loop_subdiv.h and quadric_shapes.h, the materials and
// lights pbrt_materials.h. Triangle ids: shapes in file order (an instance's shapes at each
// ObjectInstance), each shape's triangles in its own order.
#include "scene/pbrt_loader.h"

#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "scene/indexed_mesh.h"
#include "scene/loop_subdiv.h"
#include "scene/ply_file.h"
#include "scene/pbrt_materials.h"
#include "scene/pbrt_params.h"
#include "scene/pbrt_tokenizer.h"
#include "scene/quadric_shapes.h"
#include "scene/scene_builder.h"

namespace hrpp {
namespace {

constexpr int kMaxIncludeDepth = 64;

struct AreaLight {
  glm::vec3 radiance{1.0f};  // L × scale
  bool two_sided = false;
  float power = -1.0f;  // > 0: scale the radiance so the shape emits this much
  int id = 0;
};

struct GraphicsState {
  glm::dmat4 ctm{1.0};
  bool reverse_orientation = false;
  int material = -1;  // index into PbrtLoader::materials_, -1: pbrt's default (diffuse 0.5)
  std::optional<AreaLight> area_light;
};

// A shape of an ObjectBegin/ObjectEnd definition, kept in object space until instanced.
struct InstanceShape {
  IndexedMesh mesh;  // oriented (orient())
  glm::dmat4 object_to_instance{1.0};
  std::uint32_t material = 0;
  std::string where;
};

struct PendingCamera {
  glm::dmat4 world_from_camera{1.0};
  float fov_degrees = 90.0f;
};

glm::vec3 at(const glm::dmat4& m, const glm::vec3& p) {
  return glm::vec3(m * glm::dvec4(glm::dvec3(p), 1.0));
}

// pbrt-v4's front side, as hrpp's winding: normals reversed by ReverseOrientation and every
// triangle turned to face its normals (a mesh with normals); pbrt keeps the object's own
// orientation under a mirroring transform, so the winding is flipped back there (append_mesh).
bool orient(IndexedMesh& mesh, bool reverse, const glm::dmat4& m) {
  const bool mirrors = glm::determinant(glm::dmat3(m)) < 0.0;
  if (mesh.normals.empty()) return mirrors != reverse;
  if (reverse) {
    for (glm::vec3& n : mesh.normals) n = -n;
  }
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    std::uint32_t* k = &mesh.indices[t];
    const glm::vec3 c = glm::cross(mesh.positions[k[1]] - mesh.positions[k[0]],
                                   mesh.positions[k[2]] - mesh.positions[k[0]]);
    const glm::vec3 n = mesh.normals[k[0]] + mesh.normals[k[1]] + mesh.normals[k[2]];
    if (glm::dot(c, n) < 0.0f) std::swap(k[1], k[2]);
  }
  return mirrors;
}

double world_area(const IndexedMesh& mesh, const glm::dmat4& m) {
  double area = 0.0;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const glm::dvec3 a(at(m, mesh.positions[mesh.indices[t]]));
    const glm::dvec3 b(at(m, mesh.positions[mesh.indices[t + 1]]));
    const glm::dvec3 c(at(m, mesh.positions[mesh.indices[t + 2]]));
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  return area;
}

float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

class PbrtLoader {
 public:
  explicit PbrtLoader(const std::filesystem::path& file) : main_(file), dir_(file.parent_path()) {}

  Scene load() {
    scene_.name = main_.filename().string();
    parse_file(main_, main_.string(), 0);
    if (!attribute_stack_.empty()) {
      warnings_.add(main_.string() + ": " + std::to_string(attribute_stack_.size()) +
                    " AttributeBegin without AttributeEnd at the end of the file");
    }
    if (in_object_) throw Error(main_.string() + ": ObjectBegin without ObjectEnd");
    finish_camera();
    if (scene_.materials.empty()) scene_.materials.push_back(Material{});
    for (const std::string& w : warnings_.lines()) {
      scene_.warnings.push_back(w);
      std::fprintf(stderr, "hrpp: warning: %s\n", w.c_str());
    }
    return std::move(scene_);
  }

 private:
  // ---- files ----------------------------------------------------------------------------------
  // pbrt-v4 resolves a relative path against the main file's folder, else the working folder.
  std::filesystem::path resolve(const std::string& name) const {
    const std::filesystem::path p(name);
    if (p.is_absolute()) return p;
    std::error_code ec;
    const std::filesystem::path in_dir = dir_ / p;
    if (std::filesystem::exists(in_dir, ec) || !std::filesystem::exists(p, ec)) return in_dir;
    return p;
  }

  void parse_file(const std::filesystem::path& file, const std::string& from, int depth) {
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(file, ec);
    for (const std::filesystem::path& open : open_files_) {
      if (open == canonical) throw Error(from + ": " + file.string() + " includes itself");
    }
    if (depth > kMaxIncludeDepth) throw Error(from + ": Include nested too deeply");
    if (!std::filesystem::exists(file, ec))
      throw Error(from + ": " + file.string() + ": no such file");
    open_files_.push_back(canonical);
    PbrtTokenizer in(file);
    while (const std::optional<PbrtToken> t = in.next()) directive(in, *t, depth);
    open_files_.pop_back();
  }

  // ---- tokens ---------------------------------------------------------------------------------
  [[noreturn]] static void fail(const PbrtTokenizer& in, int line, const std::string& what) {
    throw Error(in.file() + ":" + std::to_string(line) + ": " + what);
  }

  static std::string string_arg(PbrtTokenizer& in, const PbrtToken& d) {
    const std::optional<PbrtToken> t = in.next();
    if (!t || t->kind != PbrtToken::kString)
      fail(in, d.line, d.text + ": expected a quoted string");
    return t->text;
  }

  static double number_arg(PbrtTokenizer& in, const PbrtToken& d) {
    const std::optional<PbrtToken> t = in.next();
    if (t && t->kind == PbrtToken::kWord) {
      char* end = nullptr;
      const double v = std::strtod(t->text.c_str(), &end);
      if (end == t->text.c_str() + t->text.size() && !t->text.empty() && std::isfinite(v)) return v;
    }
    fail(in, d.line, d.text + ": expected a number");
  }

  static std::vector<double> numbers_arg(PbrtTokenizer& in, const PbrtToken& d, std::size_t n) {
    const bool bracket = in.peek() && in.peek()->kind == PbrtToken::kOpenBracket;
    if (bracket) in.next();
    std::vector<double> v(n);
    for (double& x : v) x = number_arg(in, d);
    if (bracket) {
      const std::optional<PbrtToken> t = in.next();
      if (!t || t->kind != PbrtToken::kCloseBracket) fail(in, d.line, d.text + ": expected ]");
    }
    return v;
  }

  // ---- directives ----------------------------------------------------------------------------
  void directive(PbrtTokenizer& in, const PbrtToken& d, int depth) {
    if (d.kind != PbrtToken::kWord) {
      fail(in, d.line, "expected a directive, found \"" + d.text + "\"");
    }
    if (transform_directive(in, d) || state_directive(in, d) || scene_directive(in, d)) return;
    if (d.text == "Include" || d.text == "Import") {
      const std::string name = string_arg(in, d);
      const std::string from = in.file() + ":" + std::to_string(d.line) + ": " + d.text;
      if (d.text == "Include") {
        parse_file(resolve(name), from, depth + 1);
        return;
      }
      const GraphicsState saved = gs_;  // an Import's state changes stay inside it
      std::map<std::string, glm::dmat4> coords;
      std::swap(coords, named_coords_);
      parse_file(resolve(name), from, depth + 1);
      std::swap(coords, named_coords_);
      gs_ = saved;
      return;
    }
    fail(in, d.line, "unknown directive \"" + d.text + "\"");
  }

  bool transform_directive(PbrtTokenizer& in, const PbrtToken& d) {
    const std::string& w = d.text;
    if (w == "Translate") {
      const auto v = numbers_arg(in, d, 3);
      gs_.ctm = glm::translate(gs_.ctm, glm::dvec3(v[0], v[1], v[2]));
    } else if (w == "Scale") {
      const auto v = numbers_arg(in, d, 3);
      gs_.ctm = glm::scale(gs_.ctm, glm::dvec3(v[0], v[1], v[2]));
    } else if (w == "Rotate") {
      const auto v = numbers_arg(in, d, 4);
      const glm::dvec3 axis(v[1], v[2], v[3]);
      if (glm::length(axis) == 0.0) fail(in, d.line, "Rotate: the axis is zero");
      gs_.ctm = glm::rotate(gs_.ctm, glm::radians(v[0]), glm::normalize(axis));
    } else if (w == "LookAt") {
      gs_.ctm = gs_.ctm * look_at(in, d, numbers_arg(in, d, 9));
    } else if (w == "Transform" || w == "ConcatTransform") {
      const auto v = numbers_arg(in, d, 16);
      const glm::dmat4 m = glm::make_mat4(v.data());  // pbrt's list is column-major
      gs_.ctm = w == "Transform" ? m : gs_.ctm * m;
    } else if (w == "Identity") {
      gs_.ctm = glm::dmat4(1.0);
    } else if (w == "CoordinateSystem") {
      named_coords_[string_arg(in, d)] = gs_.ctm;
    } else if (w == "CoordSysTransform") {
      const std::string name = string_arg(in, d);
      auto it = named_coords_.find(name);
      if (it == named_coords_.end()) {
        warnings_.add(in.file() + ":" + std::to_string(d.line) + ": coordinate system \"" + name +
                      "\" is not defined: CoordSysTransform ignored");
      } else {
        gs_.ctm = it->second;
      }
    } else {
      return false;
    }
    return true;
  }

  // pbrt-v4's LookAt (util/transform.cpp): the camera-from-world matrix of a camera at eye
  // looking at look; its space is left-handed (x = up × dir).
  static glm::dmat4 look_at(const PbrtTokenizer& in, const PbrtToken& d,
                            const std::vector<double>& v) {
    const glm::dvec3 eye(v[0], v[1], v[2]), look(v[3], v[4], v[5]), up(v[6], v[7], v[8]);
    if (glm::length(look - eye) == 0.0)
      fail(in, d.line, "LookAt: eye and look-at point are the same");
    const glm::dvec3 dir = glm::normalize(look - eye);
    if (glm::length(up) == 0.0 || glm::length(glm::cross(glm::normalize(up), dir)) == 0.0) {
      fail(in, d.line, "LookAt: the up vector and the viewing direction are parallel");
    }
    const glm::dvec3 right = glm::normalize(glm::cross(glm::normalize(up), dir));
    const glm::dvec3 new_up = glm::cross(dir, right);
    glm::dmat4 world_from_camera(1.0);
    world_from_camera[0] = glm::dvec4(right, 0.0);
    world_from_camera[1] = glm::dvec4(new_up, 0.0);
    world_from_camera[2] = glm::dvec4(dir, 0.0);
    world_from_camera[3] = glm::dvec4(eye, 1.0);
    return glm::inverse(world_from_camera);
  }

  bool state_directive(PbrtTokenizer& in, const PbrtToken& d) {
    const std::string& w = d.text;
    if (w == "AttributeBegin" || w == "TransformBegin") {
      if (w == "TransformBegin")
        warn_at(in, d, "TransformBegin is deprecated in pbrt-v4: read as AttributeBegin");
      attribute_stack_.push_back(gs_);
    } else if (w == "AttributeEnd" || w == "TransformEnd") {
      if (attribute_stack_.empty()) fail(in, d.line, w + " without a matching AttributeBegin");
      gs_ = attribute_stack_.back();
      attribute_stack_.pop_back();
    } else if (w == "ReverseOrientation") {
      gs_.reverse_orientation = !gs_.reverse_orientation;
    } else if (w == "WorldBegin") {
      gs_.ctm = glm::dmat4(1.0);
      named_coords_["world"] = gs_.ctm;
    } else if (w == "WorldEnd") {  // pbrt-v3's; pbrt-v4 ends the world at the end of the file
    } else if (w == "ObjectBegin") {
      if (in_object_) fail(in, d.line, "ObjectBegin inside another ObjectBegin");
      const std::string name = string_arg(in, d);
      attribute_stack_.push_back(gs_);
      in_object_ = true;
      object_name_ = name;
      objects_[name].clear();
    } else if (w == "ObjectEnd") {
      if (!in_object_) fail(in, d.line, "ObjectEnd without ObjectBegin");
      if (attribute_stack_.empty()) fail(in, d.line, "ObjectEnd without a matching AttributeBegin");
      in_object_ = false;
      gs_ = attribute_stack_.back();
      attribute_stack_.pop_back();
    } else if (w == "ObjectInstance") {
      instance(in, d, string_arg(in, d));
    } else if (w == "ActiveTransform") {
      const std::optional<PbrtToken> t = in.next();
      if (!t || t->kind != PbrtToken::kWord)
        fail(in, d.line, "ActiveTransform: expected All, StartTime or EndTime");
      if (t->text != "All")
        warn_at(in, d, "ActiveTransform " + t->text + " (motion blur) is ignored");
    } else if (w == "TransformTimes") {
      numbers_arg(in, d, 2);
      warn_at(in, d, "TransformTimes (motion blur) is ignored");
    } else {
      return false;
    }
    return true;
  }

  bool scene_directive(PbrtTokenizer& in, const PbrtToken& d) {
    const std::string& w = d.text;
    if (w == "Shape") {
      const std::string type = string_arg(in, d);
      shape(in, d, type, PbrtParams::parse(in, d.line));
    } else if (w == "Material") {
      const std::string type = string_arg(in, d);
      gs_.material = add_material(type, PbrtParams::parse(in, d.line));
    } else if (w == "MakeNamedMaterial") {
      const std::string name = string_arg(in, d);
      const PbrtParams p = PbrtParams::parse(in, d.line);
      named_materials_[name] = add_material(p.get_string("type", ""), p);
    } else if (w == "NamedMaterial") {
      const std::string name = string_arg(in, d);
      auto it = named_materials_.find(name);
      if (it == named_materials_.end())
        fail(in, d.line, "NamedMaterial \"" + name + "\" is not defined");
      gs_.material = it->second;
    } else if (w == "Texture") {
      texture(in, d);
    } else if (w == "LightSource") {
      const std::string type = string_arg(in, d);
      const PbrtParams p = PbrtParams::parse(in, d.line);
      if (auto l = pbrt_light(type, p, gs_.ctm, warnings_)) scene_.lights.push_back(*l);
      report_unused(p, "LightSource \"" + type + "\"");
    } else if (w == "AreaLightSource") {
      area_light(in, d);
    } else if (w == "Camera") {
      camera(in, d);
    } else if (w == "Film" || w == "Sampler") {
      const std::string type = string_arg(in, d);
      const PbrtParams p = PbrtParams::parse(in, d.line);
      if (w == "Film") {
        film_width_ = p.get_int("xresolution", 1280);
        film_height_ = p.get_int("yresolution", 720);
        if (film_width_ <= 0 || film_height_ <= 0)
          fail(in, d.line, "Film: resolution must be positive");
      } else {
        const int spp = p.get_int("pixelsamples", 16);
        if (spp <= 0) fail(in, d.line, "Sampler: pixelsamples must be positive");
        scene_.film_spp = static_cast<std::uint32_t>(spp);
      }
    } else if (w == "Integrator" || w == "PixelFilter" || w == "Accelerator" || w == "ColorSpace" ||
               w == "MakeNamedMedium" || w == "Attribute") {
      const std::string type = string_arg(in, d);
      PbrtParams::parse(in, d.line);
      if (w != "Accelerator" && w != "Integrator")
        warn_at(in, d, w + " \"" + type + "\" is ignored");
    } else if (w == "Option") {
      PbrtParams::parse(in, d.line);
    } else if (w == "MediumInterface") {
      string_arg(in, d);
      if (in.peek() && in.peek()->kind == PbrtToken::kString) in.next();
      warn_at(in, d, "participating media (MediumInterface) are ignored");
    } else {
      return false;
    }
    return true;
  }

  void warn_at(const PbrtTokenizer& in, const PbrtToken& d, const std::string& what) {
    warnings_.add(in.file() + ":" + std::to_string(d.line) + ": " + what);
  }

  void report_unused(const PbrtParams& p, const std::string& what) {
    for (const std::string& u : p.unused())
      warnings_.add(p.where() + what + ": \"" + u + "\" is ignored");
  }

  // ---- materials, textures, lights -------------------------------------------------------------
  int add_material(const std::string& type, const PbrtParams& p) {
    PbrtMaterial m = pbrt_material(type, p, PbrtMaterialContext{textures_, warnings_});
    materials_.push_back(std::move(m));
    return static_cast<int>(materials_.size() - 1);
  }

  void texture(PbrtTokenizer& in, const PbrtToken& d) {
    const std::string name = string_arg(in, d);
    const std::string type = string_arg(in, d);
    const std::string cls = string_arg(in, d);
    const PbrtParams p = PbrtParams::parse(in, d.line);
    if (type != "spectrum" && type != "float" && type != "color") {
      fail(in, d.line,
           "Texture \"" + name + "\": type \"" + type + "\" is neither spectrum nor float");
    }
    const std::string file =
        cls == "imagemap" ? resolve(p.get_string("filename", "")).string() : "";
    if (cls == "imagemap" && !p.has("filename"))
      fail(in, d.line, "Texture \"" + name + "\": imagemap needs a \"string filename\"");
    textures_[name] = pbrt_texture(cls, p, textures_, file, scene_, warnings_);
  }

  void area_light(PbrtTokenizer& in, const PbrtToken& d) {
    const std::string type = string_arg(in, d);
    const PbrtParams p = PbrtParams::parse(in, d.line);
    if (type != "diffuse") {
      warn_at(in, d, "AreaLightSource \"" + type + "\" is not supported: its shapes do not emit");
      gs_.area_light.reset();
      return;
    }
    AreaLight l;
    l.radiance = p.get_rgb("L").value_or(glm::vec3(1.0f)) * p.get_float("scale", 1.0f);
    l.two_sided = p.get_bool("twosided", false);
    l.power = p.get_float("power", -1.0f);
    l.id = ++area_light_count_;
    if (p.has("filename")) warn_at(in, d, "AreaLightSource image (\"filename\") is ignored");
    report_unused(p, "AreaLightSource");
    gs_.area_light = l;
  }

  // The Scene material of the current material and area light, made once per pair.
  std::uint32_t scene_material(double area) {
    const AreaLight* l = gs_.area_light ? &*gs_.area_light : nullptr;
    const int light_id = l ? l->id : 0;
    const bool per_shape_power = l && l->power > 0.0f;
    const auto key = std::make_pair(gs_.material, light_id);
    if (!per_shape_power) {
      auto it = scene_materials_.find(key);
      if (it != scene_materials_.end()) return it->second;
    }
    Material m = gs_.material >= 0 ? materials_[gs_.material].material
                                   : Material{"diffuse", glm::vec3(0.5f)};
    if (l) {
      m.emission = glm::max(l->radiance, glm::vec3(0.0f));
      m.two_sided_emission = l->two_sided;
      if (per_shape_power && area > 0.0 && luminance(m.emission) > 0.0f) {  // pbrt-v4: L normalised
        const double k =
            static_cast<double>(l->power) / (3.14159265358979 * (l->two_sided ? 2.0 : 1.0) * area);
        m.emission *= static_cast<float>(k) / luminance(m.emission);
      }
    }
    scene_.materials.push_back(m);
    const auto index = static_cast<std::uint32_t>(scene_.materials.size() - 1);
    if (!per_shape_power) scene_materials_[key] = index;
    return index;
  }

  // pbrt's (u, v) through the material's texture mapping, to hrpp's top-down texture rows.
  void map_uvs(IndexedMesh& mesh) const {
    PbrtTexture identity;
    const PbrtTexture& t = gs_.material >= 0 && materials_[gs_.material].texture
                               ? *materials_[gs_.material].texture
                               : identity;
    for (glm::vec2& uv : mesh.uvs) {
      const glm::vec2 st = t.uv_scale * uv + t.uv_offset;
      uv = glm::vec2(st.x, 1.0f - st.y);
    }
  }

  // ---- camera -------------------------------------------------------------------------------
  void camera(PbrtTokenizer& in, const PbrtToken& d) {
    const std::string type = string_arg(in, d);
    const PbrtParams p = PbrtParams::parse(in, d.line);
    if (type != "perspective")
      fail(in, d.line, "Camera \"" + type + "\" is not supported (only \"perspective\")");
    const glm::dmat4 camera_from_world = gs_.ctm;
    if (glm::determinant(camera_from_world) == 0.0)
      fail(in, d.line, "Camera: the transform is singular");
    PendingCamera c;
    c.world_from_camera = glm::inverse(camera_from_world);
    c.fov_degrees = p.get_float("fov", 90.0f);
    if (!(c.fov_degrees > 0.0f && c.fov_degrees < 180.0f))
      fail(in, d.line, "Camera: fov must be in (0, 180) degrees");
    if (p.get_float("lensradius", 0.0f) > 0.0f)
      warn_at(in, d, "depth of field (lensradius) is ignored");
    report_unused(p, "Camera");
    named_coords_["camera"] = c.world_from_camera;
    camera_ = c;
  }

  // pbrt's fov spans the image's shorter side; hrpp's yfov its height.
  void finish_camera() {
    if (film_width_ > 0) {
      scene_.film_width = static_cast<std::uint32_t>(film_width_);
      scene_.film_height = static_cast<std::uint32_t>(film_height_);
    }
    if (!camera_) return;
    const glm::dmat4& m = camera_->world_from_camera;
    Camera cam;
    cam.name = "pbrt";
    cam.position = at(m, glm::vec3(0.0f));
    cam.forward = glm::normalize(glm::vec3(glm::dmat3(m) * glm::dvec3(0, 0, 1)));
    const glm::vec3 up = glm::vec3(glm::dmat3(m) * glm::dvec3(0, 1, 0));
    cam.up = glm::normalize(up - glm::dot(up, cam.forward) * cam.forward);
    const glm::vec3 right = glm::vec3(glm::dmat3(m) * glm::dvec3(1, 0, 0));
    cam.mirrored = glm::dot(right, glm::cross(cam.forward, cam.up)) < 0.0f;
    const double aspect = film_width_ > 0 ? double(film_width_) / film_height_ : 1280.0 / 720.0;
    const double t = std::tan(glm::radians(0.5 * camera_->fov_degrees));
    cam.yfov = static_cast<float>(2.0 * std::atan(aspect >= 1.0 ? t : t / aspect));
    scene_.cameras.push_back(cam);
  }

  // ---- shapes -------------------------------------------------------------------------------
  void shape(PbrtTokenizer& in, const PbrtToken& d, const std::string& type, const PbrtParams& p) {
    const std::string where = in.file() + ":" + std::to_string(d.line) + ": Shape \"" + type + "\"";
    IndexedMesh mesh = shape_mesh(in, d, type, p, where);
    for (const std::string& u : p.unused()) {
      static const char* const kIgnored[] = {"float alpha",
                                             "texture alpha",
                                             "vector3 S",
                                             "integer faceIndices",
                                             "float edgelength",
                                             "texture displacement",
                                             "string emissionfilename"};
      bool ignored = false;
      for (const char* k : kIgnored) ignored = ignored || u == k;
      if (!ignored) throw Error(where + ": parameter \"" + u + "\" is not one of this shape's");
      warnings_.add(where + ": \"" + u + "\" is ignored");
    }
    map_uvs(mesh);
    if (in_object_) {
      if (gs_.area_light)
        warnings_.add(where + ": area lights in object instances do not emit (as in pbrt-v4)");
      const auto saved = gs_.area_light;
      gs_.area_light.reset();
      MeshPlacement place{gs_.ctm, scene_material(0.0), false};
      gs_.area_light = saved;
      const bool flip = orient(mesh, gs_.reverse_orientation, gs_.ctm);
      if (flip) flip_all(mesh);
      objects_[object_name_].push_back(
          InstanceShape{std::move(mesh), gs_.ctm, place.material, where});
      return;
    }
    MeshPlacement place;
    place.object_to_world = gs_.ctm;
    place.flip_winding = orient(mesh, gs_.reverse_orientation, gs_.ctm);
    place.material = scene_material(
        gs_.area_light && gs_.area_light->power > 0.0f ? world_area(mesh, gs_.ctm) : 0.0);
    append_mesh(scene_, mesh, place, where);
  }

  static void flip_all(IndexedMesh& mesh) {
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
      std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
  }

  void instance(PbrtTokenizer& in, const PbrtToken& d, const std::string& name) {
    if (in_object_) fail(in, d.line, "ObjectInstance inside ObjectBegin");
    auto it = objects_.find(name);
    if (it == objects_.end()) fail(in, d.line, "ObjectInstance \"" + name + "\" is not defined");
    const std::string where =
        in.file() + ":" + std::to_string(d.line) + ": ObjectInstance \"" + name + "\"";
    for (const InstanceShape& s : it->second) {
      MeshPlacement place;
      place.object_to_world = gs_.ctm * s.object_to_instance;
      // The shape was oriented for its own transform; this instance's may mirror it again.
      place.flip_winding = (glm::determinant(glm::dmat3(place.object_to_world)) < 0.0) !=
                           (glm::determinant(glm::dmat3(s.object_to_instance)) < 0.0);
      place.material = s.material;
      append_mesh(scene_, s.mesh, place, where + " (" + s.where + ")");
    }
  }

  IndexedMesh shape_mesh(PbrtTokenizer& in, const PbrtToken& d, const std::string& type,
                         const PbrtParams& p, const std::string& where) {
    if (type == "trianglemesh") return triangle_mesh(p, where);
    if (type == "bilinearmesh") return bilinear_mesh(p, where);
    if (type == "plymesh") {
      const std::string file = p.get_string("filename", "");
      if (file.empty()) throw Error(where + ": needs a \"string filename\"");
      IndexedMesh m = read_ply_mesh(resolve(file), where);
      for (glm::vec2& uv : m.uvs) uv.y = 1.0f - uv.y;  // back to pbrt's v (read_ply_mesh flips it)
      return m;
    }
    if (type == "loopsubdiv") {
      const std::vector<glm::vec3> P = p.get_point3s("P");
      const std::vector<std::uint32_t> idx = indices(p, "indices", where);
      if (P.empty() || idx.empty())
        throw Error(where + ": needs \"point3 P\" and \"integer indices\"");
      return loop_subdivide(P, idx, p.get_int("levels", 3), where);
    }
    if (type == "sphere") {
      const float r = p.get_float("radius", 1.0f);
      return tessellate_sphere(r, p.get_float("zmin", -r), p.get_float("zmax", r),
                               p.get_float("phimax", 360.0f), quadric_segments());
    }
    if (type == "disk") {
      const float r = p.get_float("radius", 1.0f);
      return tessellate_disk(p.get_float("height", 0.0f), r, p.get_float("innerradius", 0.0f),
                             p.get_float("phimax", 360.0f), quadric_segments());
    }
    if (type == "cylinder") {
      const float r = p.get_float("radius", 1.0f);
      return tessellate_cylinder(r, p.get_float("zmin", -1.0f), p.get_float("zmax", 1.0f),
                                 p.get_float("phimax", 360.0f), quadric_segments());
    }
    fail(in, d.line,
         "Shape \"" + type +
             "\" is not supported (trianglemesh, plymesh, bilinearmesh, "
             "loopsubdiv, sphere, disk, cylinder)");
  }

  static std::vector<std::uint32_t> indices(const PbrtParams& p, const char* name,
                                            const std::string& where) {
    std::vector<std::uint32_t> out;
    for (int i : p.get_ints(name)) {
      if (i < 0) throw Error(where + ": negative vertex index " + std::to_string(i));
      out.push_back(static_cast<std::uint32_t>(i));
    }
    return out;
  }

  static void attributes(IndexedMesh& m, const PbrtParams& p, const std::string& where) {
    m.normals = p.get_point3s("N");
    m.uvs = p.get_point2s("uv");
    if (m.uvs.empty()) m.uvs = p.get_point2s("st");
    if (!m.normals.empty() && m.normals.size() != m.positions.size()) {
      throw Error(where + ": " + std::to_string(m.normals.size()) + " normals for " +
                  std::to_string(m.positions.size()) + " vertices");
    }
    if (!m.uvs.empty() && m.uvs.size() != m.positions.size()) {
      throw Error(where + ": " + std::to_string(m.uvs.size()) + " uvs for " +
                  std::to_string(m.positions.size()) + " vertices");
    }
  }

  static IndexedMesh triangle_mesh(const PbrtParams& p, const std::string& where) {
    IndexedMesh m;
    m.positions = p.get_point3s("P");
    if (m.positions.empty()) throw Error(where + ": needs \"point3 P\"");
    m.indices = indices(p, "indices", where);
    if (m.indices.empty()) {
      if (m.positions.size() != 3)
        throw Error(where + ": needs \"integer indices\" (P has " +
                    std::to_string(m.positions.size()) + " points, not 3)");
      m.indices = {0, 1, 2};
    }
    if (m.indices.size() % 3 != 0)
      throw Error(where + ": " + std::to_string(m.indices.size()) +
                  " indices, not a multiple of 3 (a face with fewer than three vertices)");
    attributes(m, p, where);
    check_mesh(m, where);
    return m;
  }

  // pbrt-v4's own conversion of a bilinear patch (q0, q1, q2, q3) to triangles (q0, q1, q3) and
  // (q0, q3, q2) (util/mesh.cpp); pbrt renders the true patch, which these two bound.
  static IndexedMesh bilinear_mesh(const PbrtParams& p, const std::string& where) {
    IndexedMesh m;
    m.positions = p.get_point3s("P");
    if (m.positions.empty()) throw Error(where + ": needs \"point3 P\"");
    std::vector<std::uint32_t> q = indices(p, "indices", where);
    if (q.empty() && m.positions.size() == 4) q = {0, 1, 2, 3};
    if (q.empty() || q.size() % 4 != 0)
      throw Error(where + ": " + std::to_string(q.size()) + " indices, not a multiple of 4");
    for (std::size_t i = 0; i < q.size(); i += 4) {
      m.indices.insert(m.indices.end(), {q[i], q[i + 1], q[i + 3], q[i], q[i + 3], q[i + 2]});
    }
    attributes(m, p, where);
    check_mesh(m, where);
    return m;
  }

  std::filesystem::path main_, dir_;
  Scene scene_;
  PbrtWarnings warnings_;
  GraphicsState gs_;
  std::vector<GraphicsState> attribute_stack_;
  std::vector<std::filesystem::path> open_files_;
  std::map<std::string, glm::dmat4> named_coords_;
  std::vector<PbrtMaterial> materials_;
  std::map<std::string, int> named_materials_;
  std::map<std::string, PbrtTexture> textures_;
  std::map<std::pair<int, int>, std::uint32_t> scene_materials_;
  std::map<std::string, std::vector<InstanceShape>> objects_;
  bool in_object_ = false;
  std::string object_name_;
  int area_light_count_ = 0;
  std::optional<PendingCamera> camera_;
  int film_width_ = 0, film_height_ = 0;
};

}  // namespace

Scene load_pbrt(const std::filesystem::path& file) { return PbrtLoader(file).load(); }

}  // namespace hrpp
