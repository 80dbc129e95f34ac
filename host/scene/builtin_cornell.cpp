// builtin:cornell: the classic Cornell box, measured data of the Cornell Program of Computer
// Graphics (https://www.graphics.cornell.edu/online/box/data.html), millimetres. Every quad is
// wound so that its geometric normal faces into the box; the light sits 0.1 mm below the ceiling
// facing down. Triangle ids: floor, ceiling, light, back wall, red (left) wall, green (right) wall,
// short block (top, 4 sides), tall block (top, 4 sides); two triangles per quad (a,b,c), (a,c,d).
#include <cmath>

#include "scene/load_scene.h"

namespace hrpp {
namespace {

using V = glm::vec3;

void add_quad(Scene& s, V a, V b, V c, V d, std::uint32_t material) {
  const V n = glm::normalize(glm::cross(b - a, c - a));
  const V tri[2][3] = {{a, b, c}, {a, c, d}};
  const glm::vec2 uv[2][3] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
  for (int i = 0; i < 2; ++i) {
    s.triangles.push_back(Triangle{tri[i][0], tri[i][1], tri[i][2]});
    TriangleShading sh;
    sh.n0 = sh.n1 = sh.n2 = n;
    sh.uv0 = uv[i][0];
    sh.uv1 = uv[i][1];
    sh.uv2 = uv[i][2];
    sh.material = material;
    s.shading.push_back(sh);
  }
}

Material diffuse(const char* name, V color) {
  Material m;
  m.name = name;
  m.base_color = color;
  return m;
}

}  // namespace

Scene builtin_cornell() {
  Scene s;
  s.name = "builtin:cornell";
  enum : std::uint32_t { kWhite, kRed, kGreen, kLight };
  s.materials.push_back(diffuse("white", V(0.725f, 0.71f, 0.68f)));
  s.materials.push_back(diffuse("red", V(0.63f, 0.065f, 0.05f)));
  s.materials.push_back(diffuse("green", V(0.14f, 0.45f, 0.091f)));
  Material light = diffuse("light", V(0.78f));
  light.emission = V(17.0f, 12.0f, 4.0f);
  s.materials.push_back(light);

  // Floor, ceiling.
  add_quad(s, V(552.8f, 0, 0), V(0, 0, 0), V(0, 0, 559.2f), V(549.6f, 0, 559.2f), kWhite);
  add_quad(s, V(556.0f, 548.8f, 0), V(556.0f, 548.8f, 559.2f), V(0, 548.8f, 559.2f),
           V(0, 548.8f, 0), kWhite);
  // Light: corner + s·u + t·v, facing down (u × v = -y).
  const V corner(343.0f, 548.7f, 227.0f), eu(0, 0, 105.0f), ev(-130.0f, 0, 0);
  add_quad(s, corner, corner + eu, corner + eu + ev, corner + ev, kLight);
  // Back wall, red wall (x ≈ 556, left in the image), green wall (x = 0).
  add_quad(s, V(549.6f, 0, 559.2f), V(0, 0, 559.2f), V(0, 548.8f, 559.2f),
           V(556.0f, 548.8f, 559.2f), kWhite);
  add_quad(s, V(552.8f, 0, 0), V(549.6f, 0, 559.2f), V(556.0f, 548.8f, 559.2f),
           V(556.0f, 548.8f, 0), kRed);
  add_quad(s, V(0, 0, 559.2f), V(0, 0, 0), V(0, 548.8f, 0), V(0, 548.8f, 559.2f), kGreen);
  // Short block.
  add_quad(s, V(130, 165, 65), V(82, 165, 225), V(240, 165, 272), V(290, 165, 114), kWhite);
  add_quad(s, V(290, 0, 114), V(290, 165, 114), V(240, 165, 272), V(240, 0, 272), kWhite);
  add_quad(s, V(130, 0, 65), V(130, 165, 65), V(290, 165, 114), V(290, 0, 114), kWhite);
  add_quad(s, V(82, 0, 225), V(82, 165, 225), V(130, 165, 65), V(130, 0, 65), kWhite);
  add_quad(s, V(240, 0, 272), V(240, 165, 272), V(82, 165, 225), V(82, 0, 225), kWhite);
  // Tall block.
  add_quad(s, V(423, 330, 247), V(265, 330, 296), V(314, 330, 456), V(472, 330, 406), kWhite);
  add_quad(s, V(423, 0, 247), V(423, 330, 247), V(472, 330, 406), V(472, 0, 406), kWhite);
  add_quad(s, V(472, 0, 406), V(472, 330, 406), V(314, 330, 456), V(314, 0, 456), kWhite);
  add_quad(s, V(314, 0, 456), V(314, 330, 456), V(265, 330, 296), V(265, 0, 296), kWhite);
  add_quad(s, V(265, 0, 296), V(265, 330, 296), V(423, 330, 247), V(423, 0, 247), kWhite);

  Light area;
  area.type = LightType::kAreaQuad;
  area.color = light.emission;
  area.position = corner;
  area.edge_u = eu;
  area.edge_v = ev;
  s.lights.push_back(area);

  Camera cam;
  cam.name = "cornell";
  cam.position = V(278.0f, 273.0f, -800.0f);
  cam.forward = V(0, 0, 1);
  cam.up = V(0, 1, 0);
  cam.yfov = 2.0f * std::atan(0.0125f / 0.035f);
  // aspect 0: from the image size (the measured film is square; render square for the classic view)
  s.cameras.push_back(cam);
  return s;
}

}  // namespace hrpp
