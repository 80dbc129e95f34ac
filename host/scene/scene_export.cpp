#include "scene/scene_export.h"

#include <vector>

#include <nlohmann/json.hpp>

namespace hrpp {
namespace {

nlohmann::json vec(const glm::vec3& v) { return {v.x, v.y, v.z}; }

nlohmann::json material_json(const Material& m) {
  return {{"name", m.name},
          {"base_color", vec(m.base_color)},
          {"textured", m.base_color_texture >= 0},
          {"metallic_roughness_textured", m.metallic_roughness_texture >= 0},
          {"emissive_textured", m.emissive_texture >= 0},
          {"metallic", m.metallic},
          {"roughness", m.roughness},
          {"transmission", m.transmission},
          {"ior", m.ior},
          {"specular", m.specular},
          {"specular_color", vec(m.specular_color)},
          {"emission", vec(m.emission)},
          {"two_sided_emission", m.two_sided_emission}};
}

nlohmann::json light_json(const Light& l) {
  return {{"type", name_in(kLightTypeNames, l.type)},
          {"color", vec(l.color)},
          {"position", vec(l.position)},
          {"direction", vec(l.direction)},
          {"edge_u", vec(l.edge_u)},
          {"edge_v", vec(l.edge_v)},
          {"inner_cone", l.inner_cone},
          {"outer_cone", l.outer_cone}};
}

nlohmann::json camera_json(const Camera& c) {
  return {{"name", c.name},
          {"position", vec(c.position)},
          {"forward", vec(c.forward)},
          {"up", vec(c.up)},
          {"yfov", c.yfov},
          {"aspect", c.aspect},
          {"mirrored", c.mirrored}};
}

}  // namespace

std::string scene_json(const Scene& scene) {
  std::vector<float> positions;
  positions.reserve(scene.triangles.size() * 9);
  std::vector<float> normals;  // vertex normals, 9 floats a triangle (zeros: none)
  normals.reserve(scene.triangles.size() * 9);
  std::vector<std::uint32_t> material_of;
  material_of.reserve(scene.triangles.size());
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const Triangle& t = scene.triangles[i];
    const TriangleShading& s = scene.shading[i];
    for (const glm::vec3& v : {t.v0, t.v1, t.v2})
      positions.insert(positions.end(), {v.x, v.y, v.z});
    for (const glm::vec3& n : {s.n0, s.n1, s.n2}) normals.insert(normals.end(), {n.x, n.y, n.z});
    material_of.push_back(s.material);
  }
  nlohmann::json j = {{"format", "hrpp scene export 1"},
                      {"name", scene.name},
                      {"positions", positions},
                      {"normals", normals},
                      {"material_of", material_of},
                      {"materials", nlohmann::json::array()},
                      {"lights", nlohmann::json::array()},
                      {"cameras", nlohmann::json::array()}};
  for (const Material& m : scene.materials) j["materials"].push_back(material_json(m));
  for (const Light& l : scene.lights) j["lights"].push_back(light_json(l));
  for (const Camera& c : scene.cameras) j["cameras"].push_back(camera_json(c));
  return j.dump() + "\n";
}

}  // namespace hrpp
