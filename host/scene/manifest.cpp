// Scene manifests (*.scene.json, spec: scenes/README.md): glTF files and quads placed, refitted
// and re-materialed, plus lights and a camera. Triangle ids: objects in listed order (a glTF in its
// own flattened order), then the area lights' quads.
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "scene/load_scene.h"
#include "scene/obj_file.h"
#include "scene/ply_file.h"

namespace hrpp {
namespace {

using nlohmann::json;

std::string one_line(std::string s) {
  for (char& c : s) {
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  }
  return s;
}

class ManifestLoader {
 public:
  explicit ManifestLoader(const std::filesystem::path& file)
      : file_(file), name_(file.string()), dir_(file.parent_path()) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw Error(one_line(name_ + ": " + (key.empty() ? "" : key + ": ") + what));
  }

  Scene load() {
    std::ifstream in(file_, std::ios::binary);
    std::error_code ec;
    if (!std::filesystem::exists(file_, ec)) fail("", "no such file");
    if (std::filesystem::is_directory(file_, ec)) fail("", "is a directory");
    if (!in) fail("", "cannot open for reading");
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    json doc;
    try {
      doc = json::parse(text);
    } catch (const json::parse_error& e) {
      std::string msg = e.what();
      if (auto p = msg.find("] "); msg.rfind("[json.exception", 0) == 0 && p != std::string::npos) {
        msg = msg.substr(p + 2);
      }
      fail("", "JSON syntax error at byte " + std::to_string(e.byte) + ": " + msg);
    } catch (const json::exception& e) {  // e.g. out_of_range.406: a number like 1e999
      std::string msg = e.what();
      if (auto p = msg.find("] "); msg.rfind("[json.exception", 0) == 0 && p != std::string::npos) {
        msg = msg.substr(p + 2);
      }
      fail("", "JSON error: " + msg);
    }
    if (!doc.is_object()) fail("", "the top level must be a JSON object");
    check_keys(doc, "", {"name", "objects", "lights", "camera"});

    Scene scene;
    scene.name = file_.filename().string();
    if (doc.contains("name")) scene.name = string(doc["name"], "name");
    if (!doc.contains("objects")) fail("objects", "missing (an array of objects is required)");
    const json& objects = doc["objects"];
    if (!objects.is_array()) fail("objects", "expected an array");
    // Sized once: growing by doubling would hold two copies of a large scene at its last step.
    const std::size_t triangles = load_meshes(objects) + 2 * light_count(doc);
    scene.triangles.reserve(triangles);
    scene.shading.reserve(triangles);
    for (std::size_t i = 0; i < objects.size(); ++i) {
      load_object(scene, objects[i], "objects[" + std::to_string(i) + "]");
    }
    std::vector<Camera> gltf_cameras = std::move(scene.cameras);
    scene.cameras.clear();
    if (doc.contains("lights")) {
      const json& lights = doc["lights"];
      if (!lights.is_array()) fail("lights", "expected an array");
      for (std::size_t i = 0; i < lights.size(); ++i) {
        load_light(scene, lights[i], "lights[" + std::to_string(i) + "]");
      }
    }
    if (doc.contains("camera")) scene.cameras.push_back(load_camera(doc["camera"], "camera"));
    for (Camera& c : gltf_cameras) scene.cameras.push_back(std::move(c));
    return scene;
  }

 private:
  // ---- typed access --------------------------------------------------------------------------
  void check_keys(const json& obj, const std::string& path,
                  std::initializer_list<const char*> allowed) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      bool ok = false;
      for (const char* a : allowed) ok = ok || it.key() == a;
      if (!ok) {
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        fail(join(path, it.key()), "unknown key (allowed here: " + list + ")");
      }
    }
  }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  const json& object(const json& j, const std::string& path) const {
    if (!j.is_object()) fail(path, "expected an object");
    return j;
  }

  std::string string(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "expected a string");
    return j.get<std::string>();
  }

  float number(const json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, "expected a number");
    const double d = j.get<double>();
    if (!std::isfinite(d) || std::fabs(d) > std::numeric_limits<float>::max()) {
      fail(path, "number out of range");
    }
    return static_cast<float>(d);
  }

  std::vector<float> numbers(const json& j, const std::string& path, std::size_t n) const {
    if (!j.is_array() || j.size() != n) {
      fail(path, "expected an array of " + std::to_string(n) + " numbers");
    }
    std::vector<float> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = number(j[i], path + "[" + std::to_string(i) + "]");
    return v;
  }

  glm::vec3 vec3(const json& j, const std::string& path) const {
    const std::vector<float> v = numbers(j, path, 3);
    return glm::vec3(v[0], v[1], v[2]);
  }

  glm::vec3 non_negative_rgb(const json& j, const std::string& path) const {
    const glm::vec3 c = vec3(j, path);
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(path, "must not be negative");
    return c;
  }

  // ---- objects -------------------------------------------------------------------------------
  void load_object(Scene& scene, const json& j, const std::string& path) {
    object(j, path);
    check_keys(j, path, {"gltf", "mesh", "quad", "fit", "transform", "material", "specular"});
    const int sources = int(j.contains("gltf")) + int(j.contains("mesh")) + int(j.contains("quad"));
    if (sources != 1) fail(path, "needs exactly one of \"gltf\", \"mesh\" or \"quad\"");

    Scene part;
    if (const char* key = mesh_key(j)) {
      part = take_mesh(string(j[key], path + "." + key));
    } else {
      const std::string qp = path + ".quad";
      const json& q = object(j["quad"], qp);
      check_keys(q, qp, {"corner", "u", "v"});
      for (const char* k : {"corner", "u", "v"}) {
        if (!q.contains(k)) fail(join(qp, k), "missing");
      }
      Material grey;
      grey.name = "quad";
      part.materials.push_back(grey);
      add_quad(part, vec3(q["corner"], qp + ".corner"), vec3(q["u"], qp + ".u"),
               vec3(q["v"], qp + ".v"), 0);
    }

    glm::mat4 m(1.0f);
    if (j.contains("fit")) m = fit_matrix(part, j["fit"], path + ".fit");
    if (j.contains("transform")) m = transform_matrix(j["transform"], path + ".transform") * m;
    apply(part, m);

    if (j.contains("material")) {
      const Material mat = load_material(j["material"], path + ".material");
      part.materials.assign(1, mat);
      part.textures.clear();
      for (TriangleShading& s : part.shading) {  // the override's colour alone
        s.material = 0;
        s.c0 = s.c1 = s.c2 = kNoVertexColor;
      }
    }
    if (j.contains("specular")) {  // the file's specular layers, scaled (0: Lambertian)
      const float f = number(j["specular"], path + ".specular");
      if (!(f >= 0.0f && f <= 1.0f)) fail(path + ".specular", "must be in [0, 1]");
      for (Material& mat : part.materials) mat.specular *= f;
    }
    append(scene, std::move(part));
  }

  // ---- meshes: each glTF file loaded once, before the objects ---------------------------------
  struct Mesh {
    Scene scene;   // as loaded, before an object's fit, transform and material
    int uses = 0;  // objects still to take it
  };

  // Loads every object's glTF (objects may share a file: it is loaded once) and returns the
  // objects' triangle count; objects that are not valid are left to load_object's errors.
  std::size_t load_meshes(const json& objects) {
    std::size_t triangles = 0;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      const json& j = objects[i];
      if (!j.is_object()) continue;
      if (j.contains("quad")) triangles += 2;
      const char* key = mesh_key(j);
      if (key == nullptr) continue;
      const std::string path = "objects[" + std::to_string(i) + "]." + key;
      const std::string rel = string(j[key], path);
      auto [it, added] = meshes_.try_emplace(rel);
      if (added) it->second.scene = read_mesh(rel, path);
      ++it->second.uses;
      triangles += it->second.scene.triangles.size();
    }
    return triangles;
  }

  // An object's mesh file key: "gltf" (a glTF file) or "mesh" (glTF, OBJ or PLY); none: null.
  static const char* mesh_key(const json& j) {
    if (j.contains("gltf")) return "gltf";
    return j.contains("mesh") ? "mesh" : nullptr;
  }

  // The mesh of an object's "gltf" or "mesh": a copy, or the mesh itself at its last use (freed then).
  Scene take_mesh(const std::string& rel) {
    auto it = meshes_.find(rel);
    if (--it->second.uses > 0) return it->second.scene;
    Scene last = std::move(it->second.scene);
    meshes_.erase(it);
    return last;
  }

  Scene read_mesh(const std::string& rel, const std::string& path) const {
    const std::filesystem::path mesh = dir_ / rel;
    std::error_code ec;
    if (!std::filesystem::exists(mesh, ec)) {
      std::string msg = "mesh file " + mesh.string() + " not found";
      for (const auto& part_name : std::filesystem::path(rel)) {
        if (part_name == "fetched") {
          msg += " (run tools/fetch-scenes.sh)";
          break;
        }
      }
      fail(path, msg);
    }
    try {
      const std::string ext = mesh.extension().string();
      if (ext == ".obj" || ext == ".OBJ") return load_obj_file(mesh);
      if (ext == ".ply" || ext == ".PLY") return load_ply_file(mesh);
      return load_gltf(mesh);
    } catch (const Error& e) {
      fail(path, e.what());
    }
  }

  static std::size_t light_count(const json& doc) {
    const auto it = doc.find("lights");
    return it != doc.end() && it->is_array() ? it->size() : 0;
  }

  glm::mat4 fit_matrix(const Scene& part, const json& j, const std::string& path) const {
    object(j, path);
    check_keys(j, path, {"base", "size"});
    if (!j.contains("size")) fail(path + ".size", "missing");
    const float size = number(j["size"], path + ".size");
    if (!(size > 0.0f)) fail(path + ".size", "must be positive");
    const glm::vec3 base = j.contains("base") ? vec3(j["base"], path + ".base") : glm::vec3(0.0f);
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const Triangle& t : part.triangles) {
      for (const glm::vec3& v : {t.v0, t.v1, t.v2}) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
      }
    }
    if (part.triangles.empty()) return glm::mat4(1.0f);
    const glm::vec3 ext = hi - lo;
    const float largest = std::max(ext.x, std::max(ext.y, ext.z));
    const float s = largest > 0.0f ? size / largest : 1.0f;
    const glm::vec3 bottom_centre(0.5f * (lo.x + hi.x), lo.y, 0.5f * (lo.z + hi.z));
    // p' = s·(p − bottom_centre) + base
    glm::mat4 m = glm::translate(glm::mat4(1.0f), base);
    m = glm::scale(m, glm::vec3(s));
    m = glm::translate(m, -bottom_centre);
    return m;
  }

  glm::mat4 transform_matrix(const json& j, const std::string& path) const {
    object(j, path);
    check_keys(j, path, {"matrix", "translate", "rotate_deg", "scale"});
    if (j.contains("matrix")) {
      if (j.contains("translate") || j.contains("rotate_deg") || j.contains("scale")) {
        fail(path, "\"matrix\" excludes \"translate\", \"rotate_deg\" and \"scale\"");
      }
      const std::vector<float> v = numbers(j["matrix"], path + ".matrix", 16);
      return glm::make_mat4(v.data());  // column-major, as glTF
    }
    glm::vec3 t(0.0f), r(0.0f), s(1.0f);
    if (j.contains("translate")) t = vec3(j["translate"], path + ".translate");
    if (j.contains("rotate_deg")) r = vec3(j["rotate_deg"], path + ".rotate_deg");
    if (j.contains("scale")) {
      const json& sj = j["scale"];
      if (sj.is_number()) {
        s = glm::vec3(number(sj, path + ".scale"));
      } else if (sj.is_array()) {
        s = vec3(sj, path + ".scale");
      } else {
        fail(path + ".scale", "expected a number or an array of 3 numbers");
      }
    }
    // Scale, then rotate about X, then Y, then Z, then translate.
    glm::mat4 m = glm::translate(glm::mat4(1.0f), t);
    m = glm::rotate(m, glm::radians(r.z), glm::vec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(r.y), glm::vec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(r.x), glm::vec3(1, 0, 0));
    return glm::scale(m, s);
  }

  static void apply(Scene& part, const glm::mat4& m) {
    if (m == glm::mat4(1.0f)) return;
    const glm::mat3 lin(m);
    const glm::mat3 nm = glm::transpose(glm::inverse(lin));
    auto point = [&](glm::vec3 p) { return glm::vec3(m * glm::vec4(p, 1.0f)); };
    auto normal = [&](glm::vec3 n) {
      if (n == glm::vec3(0.0f)) return n;
      const glm::vec3 t = nm * n;
      const float len = glm::length(t);
      return len > 0.0f && std::isfinite(len) ? t / len : glm::vec3(0.0f);
    };
    auto direction = [&](glm::vec3 d) {
      const glm::vec3 t = lin * d;
      const float len = glm::length(t);
      return len > 0.0f ? t / len : d;
    };
    for (Triangle& t : part.triangles) {
      t.v0 = point(t.v0);
      t.v1 = point(t.v1);
      t.v2 = point(t.v2);
    }
    for (TriangleShading& s : part.shading) {
      s.n0 = normal(s.n0);
      s.n1 = normal(s.n1);
      s.n2 = normal(s.n2);
    }
    for (Light& l : part.lights) {
      l.position = point(l.position);
      l.direction = direction(l.direction);
      l.edge_u = lin * l.edge_u;
      l.edge_v = lin * l.edge_v;
    }
    for (Camera& c : part.cameras) {
      c.position = point(c.position);
      c.forward = direction(c.forward);
      glm::vec3 up = lin * c.up;
      up -= glm::dot(up, c.forward) * c.forward;
      if (glm::length(up) > 0.0f) c.up = glm::normalize(up);
    }
  }

  static void append(Scene& scene, Scene&& part) {
    const auto mat_offset = static_cast<std::uint32_t>(scene.materials.size());
    const int tex_offset = static_cast<int>(scene.textures.size());
    for (Material& m : part.materials) {
      for (int* t : {&m.base_color_texture, &m.metallic_roughness_texture, &m.emissive_texture})
        if (*t >= 0) *t += tex_offset;
      scene.materials.push_back(std::move(m));
    }
    for (Texture& t : part.textures) scene.textures.push_back(std::move(t));
    scene.triangles.insert(scene.triangles.end(), part.triangles.begin(), part.triangles.end());
    for (TriangleShading& s : part.shading) {
      s.material += mat_offset;
      scene.shading.push_back(s);
    }
    for (Light& l : part.lights) scene.lights.push_back(l);
    for (Camera& c : part.cameras) scene.cameras.push_back(std::move(c));
    for (std::string& w : part.warnings) scene.warnings.push_back(std::move(w));
  }

  static void add_quad(Scene& s, glm::vec3 corner, glm::vec3 u, glm::vec3 v,
                       std::uint32_t material) {
    const glm::vec3 c = glm::cross(u, v);
    const float len = glm::length(c);
    const glm::vec3 n = len > 0.0f ? c / len : glm::vec3(0.0f);
    const glm::vec3 p[4] = {corner, corner + u, corner + u + v, corner + v};
    const glm::vec2 uv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const int tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (const auto& t : tris) {
      s.triangles.push_back(Triangle{p[t[0]], p[t[1]], p[t[2]]});
      TriangleShading sh;
      sh.n0 = sh.n1 = sh.n2 = n;
      sh.uv0 = uv[t[0]];
      sh.uv1 = uv[t[1]];
      sh.uv2 = uv[t[2]];
      sh.material = material;
      s.shading.push_back(sh);
    }
  }

  // ---- materials, lights, camera -------------------------------------------------------------
  Material load_material(const json& j, const std::string& path) const {
    object(j, path);
    if (!j.contains("type")) fail(path + ".type", "missing (diffuse, metal, glass or emissive)");
    const std::string type = string(j["type"], path + ".type");
    Material m;
    m.name = type;
    if (type == "diffuse") {
      check_keys(j, path, {"type", "color"});
      if (j.contains("color")) m.base_color = non_negative_rgb(j["color"], path + ".color");
      m.metallic = 0.0f;
      m.roughness = 1.0f;
    } else if (type == "metal") {
      check_keys(j, path, {"type", "color", "roughness"});
      m.base_color = glm::vec3(0.9f);
      m.roughness = 0.2f;
      if (j.contains("color")) m.base_color = non_negative_rgb(j["color"], path + ".color");
      if (j.contains("roughness")) m.roughness = number(j["roughness"], path + ".roughness");
      if (m.roughness < 0.0f || m.roughness > 1.0f) fail(path + ".roughness", "must be in [0, 1]");
      m.metallic = 1.0f;
    } else if (type == "glass") {
      check_keys(j, path, {"type", "ior", "color"});
      m.base_color = glm::vec3(1.0f);
      if (j.contains("color")) m.base_color = non_negative_rgb(j["color"], path + ".color");
      if (j.contains("ior")) m.ior = number(j["ior"], path + ".ior");
      if (!(m.ior >= 1.0f)) fail(path + ".ior", "must be at least 1");
      m.metallic = 0.0f;
      m.roughness = 0.0f;
      m.transmission = 1.0f;
    } else if (type == "emissive") {
      check_keys(j, path, {"type", "emission", "strength"});
      if (!j.contains("emission")) fail(path + ".emission", "missing");
      float strength = 1.0f;
      if (j.contains("strength")) strength = number(j["strength"], path + ".strength");
      if (strength < 0.0f) fail(path + ".strength", "must not be negative");
      m.base_color = glm::vec3(0.0f);
      m.emission = non_negative_rgb(j["emission"], path + ".emission") * strength;
    } else {
      fail(path + ".type", "unknown material type \"" + type +
                               "\" (expected diffuse, metal, glass or emissive)");
    }
    return m;
  }

  void load_light(Scene& scene, const json& j, const std::string& path) {
    object(j, path);
    if (!j.contains("type")) fail(path + ".type", "missing (area, point or environment)");
    const std::string type = string(j["type"], path + ".type");
    auto need = [&](const char* key) -> const json& {
      if (!j.contains(key)) fail(join(path, key), "missing");
      return j[key];
    };
    Light l;
    if (type == "area") {
      check_keys(j, path, {"type", "corner", "u", "v", "radiance"});
      l.type = LightType::kAreaQuad;
      l.position = vec3(need("corner"), path + ".corner");
      l.edge_u = vec3(need("u"), path + ".u");
      l.edge_v = vec3(need("v"), path + ".v");
      l.color = non_negative_rgb(need("radiance"), path + ".radiance");
      if (glm::length(glm::cross(l.edge_u, l.edge_v)) == 0.0f) {
        fail(path, "the quad has zero area (u and v are parallel or zero)");
      }
    } else if (type == "point") {
      check_keys(j, path, {"type", "position", "intensity"});
      l.type = LightType::kPoint;
      l.position = vec3(need("position"), path + ".position");
      l.color = non_negative_rgb(need("intensity"), path + ".intensity");
    } else if (type == "environment") {
      check_keys(j, path, {"type", "radiance"});
      l.type = LightType::kEnvironment;
      l.color = non_negative_rgb(need("radiance"), path + ".radiance");
    } else {
      fail(path + ".type",
           "unknown light type \"" + type + "\" (expected area, point or environment)");
    }
    scene.lights.push_back(l);
    if (l.type == LightType::kAreaQuad) {
      // The quad's triangles come after every object (ids), in the order the lights are listed.
      Material m;
      m.name = "area light " + std::to_string(scene.lights.size() - 1);
      m.base_color = glm::vec3(0.0f);
      m.emission = l.color;
      scene.materials.push_back(m);
      add_quad(scene, l.position, l.edge_u, l.edge_v,
               static_cast<std::uint32_t>(scene.materials.size() - 1));
    }
  }

  Camera load_camera(const json& j, const std::string& path) const {
    object(j, path);
    check_keys(j, path, {"position", "target", "up", "yfov_deg"});
    for (const char* k : {"position", "target"}) {
      if (!j.contains(k)) fail(join(path, k), "missing");
    }
    Camera c;
    c.name = "manifest";
    c.position = vec3(j["position"], path + ".position");
    const glm::vec3 target = vec3(j["target"], path + ".target");
    glm::vec3 up(0, 1, 0);
    if (j.contains("up")) up = vec3(j["up"], path + ".up");
    float yfov_deg = 40.0f;
    if (j.contains("yfov_deg")) yfov_deg = number(j["yfov_deg"], path + ".yfov_deg");
    if (!(yfov_deg > 0.0f && yfov_deg < 180.0f)) fail(path + ".yfov_deg", "must be in (0, 180)");
    const glm::vec3 f = target - c.position;
    if (!(glm::length(f) > 0.0f)) fail(path, "position and target coincide");
    c.forward = glm::normalize(f);
    up -= glm::dot(up, c.forward) * c.forward;
    if (!(glm::length(up) > 1e-6f)) fail(path + ".up", "is parallel to the view direction");
    c.up = glm::normalize(up);
    c.yfov = glm::radians(yfov_deg);
    return c;
  }

  std::filesystem::path file_;
  std::string name_;
  std::filesystem::path dir_;
  std::map<std::string, Mesh> meshes_;  // by the objects' "gltf" path
};

}  // namespace

Scene load_manifest(const std::filesystem::path& file) { return ManifestLoader(file).load(); }

}  // namespace hrpp
