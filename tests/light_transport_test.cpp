// host/render/ + shaders/render_shade.comp: direct light against closed forms on the Vulkan
// device (lavapipe here), under the validation layer; the ClosedForm tests also on the CPU
// reference renderer (host/cpu_render/). A receiver close to a two-sided emissive
// square (gaps 1e-4..1, the scene translated by 0, 1e2 and 1e4), the Cornell box with its light
// hung at a gap below the ceiling, point/spot/directional lights over a diffuse plane (with
// blockers before and behind the light), a diffuse convex body in a constant environment, a
// smooth dielectric's Fresnel at normal incidence, metallic-roughness and emissive textures, and
// the shadow-ray construction of shaders/lib/offset_ray.glsl against its C++ mirror
// (host/trace/offset_ray.h), bit for bit.
#include <algorithm>
#include <bit>
#include <cmath>
#include <ostream>
#include <cstdint>
#include <cstdio>
#include <random>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "vk/compute_pipeline.h"
#include "vk/embedded_shaders.h"
#include "vk/storage_buffer.h"
#include "vk/vulkan_context.h"
#include "cpu_render/cpu_renderer.h"
#include "gpu_test_context.h"
#include "render/wavefront_renderer.h"
#include "render_interface.h"
#include "scene/load_scene.h"
#include "trace/offset_ray.h"

namespace hrpp {
namespace {

using V = glm::vec3;
constexpr double kPi = 3.14159265358979323846;

using test::context;

// Where a closed-form test renders: the kernels on the device, or the CPU reference renderer
// (host/cpu_render/), which has to meet the same closed forms on its own.
enum class Backend { kDevice, kCpu };

RenderResult render(const Scene& scene, const RenderConfig& config,
                    Backend backend = Backend::kDevice) {
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene, BvhConfig{}), scene);
  if (backend == Backend::kCpu) return CpuRenderer(scene, bvh, config).render();
  WavefrontRenderer renderer(context(), scene, bvh, config);
  return renderer.render();
}

void PrintTo(Backend b, std::ostream* os) { *os << (b == Backend::kCpu ? "cpu" : "device"); }

class ClosedForm : public testing::TestWithParam<Backend> {};

std::string backend_name(const testing::TestParamInfo<Backend>& info) {
  return info.param == Backend::kCpu ? "CpuReference" : "Device";
}

// size × size pixels, spp samples, camera `camera`, direct light only.
RenderConfig direct_only(std::uint32_t size, std::uint32_t spp, std::uint32_t camera = 0) {
  RenderConfig c;
  c.width = c.height = size;
  c.spp = spp;
  c.seed = 17;
  c.camera = camera;
  c.max_depth = 1;
  return c;
}

struct Estimate {
  double mean = 0.0;
  double se = 0.0;  // standard error of the mean over pixels (channels averaged per pixel)
};

Estimate estimate(const std::vector<float>& rgb) {
  const std::size_t n = rgb.size() / 3;
  std::vector<double> px(n);
  for (std::size_t i = 0; i < n; ++i) px[i] = (rgb[3 * i] + rgb[3 * i + 1] + rgb[3 * i + 2]) / 3.0;
  Estimate e;
  for (double p : px) e.mean += p;
  e.mean /= static_cast<double>(n);
  double v = 0.0;
  for (double p : px) v += (p - e.mean) * (p - e.mean);
  e.se = std::sqrt(v / static_cast<double>(n - 1) / static_cast<double>(n));
  return e;
}

// Two triangles (c, c+u, c+u+v), (c, c+u+v, c+v), facing along u × v.
void add_quad(Scene& s, V c, V u, V v, std::uint32_t material) {
  for (const Triangle& t : {Triangle{c, c + u, c + u + v}, Triangle{c, c + u + v, c + v}}) {
    s.triangles.push_back(t);
    TriangleShading sh;
    sh.material = material;
    s.shading.push_back(sh);
  }
}

std::uint32_t add_material(Scene& s, V albedo, V emission = V(0.0f)) {
  Material m;
  m.base_color = albedo;
  m.emission = emission;
  s.materials.push_back(m);
  return static_cast<std::uint32_t>(s.materials.size() - 1);
}

// A pinhole camera with a narrow field (0.02 rad: it sees a patch 1% as wide as its distance),
// so the pixels measure the radiance of (nearly) one point.
Camera narrow_camera(V position, V forward, V up, float yfov = 0.02f) {
  Camera cam;
  cam.position = position;
  cam.forward = forward;
  cam.up = up;
  cam.yfov = yfov;
  return cam;
}

Camera looking_at(V position, V target, float yfov) {
  const V f = glm::normalize(target - position);
  const V up = glm::normalize(glm::cross(glm::cross(f, V(0, 1, 0)), f));
  return narrow_camera(position, f, up, yfov);
}

// Irradiance at distance d above the centre of a parallel Lambertian rectangle 2a × 2b of
// radiance L: four rectangles seen from above a corner, each with the form factor
// F = (x/√(1+x²) atan(y/√(1+x²)) + y/√(1+y²) atan(x/√(1+y²))) / 2π, x = a/d, y = b/d, and
// E = π L · 4F. d → 0 gives π L.
double irradiance_above_centre(double radiance, double a, double b, double d) {
  const double x = a / d, y = b / d;
  const double rx = std::sqrt(1.0 + x * x), ry = std::sqrt(1.0 + y * y);
  return 2.0 * radiance * (x / rx * std::atan(y / rx) + y / ry * std::atan(x / ry));
}

// How far host/trace/offset_ray.h moves p off a surface with normal n (one coordinate axis).
float offset_distance(V p, V n) { return glm::length(offset_ray_origin(p, n) - p); }

void expect_no_validation_messages() { EXPECT_EQ(context().validation_messages(), 0u); }

// --- A receiver close to a two-sided emitter ------------------------------------------------

constexpr float kCeilingY = 0.5f;
constexpr float kCentre = 0.3f;  // x and z of the emitter's centre
constexpr float kCeilingAlbedo = 0.8f;

// A 2 × 2 ceiling (albedo 0.8, facing down) at y = 0.5 and a two-sided emissive square of
// half-side `gap` and radiance 1 at `gap` below it (so every gap has the same irradiance), all
// moved by shift·(1, 1, 1); camera 0 sits halfway in the gap above the square's centre and
// looks up at the ceiling.
Scene near_emitter_scene(float gap, float shift) {
  Scene s;
  s.name = "test:near-emitter";
  const V t(shift);
  const std::uint32_t ceiling = add_material(s, V(kCeilingAlbedo));
  const std::uint32_t light = add_material(s, V(0.0f), V(1.0f));
  add_quad(s, t + V(kCentre - 1.0f, kCeilingY, kCentre - 1.0f), V(2, 0, 0), V(0, 0, 2), ceiling);
  const float y = kCeilingY - gap;
  add_quad(s, t + V(kCentre - gap, y, kCentre - gap), V(2 * gap, 0, 0), V(0, 0, 2 * gap), light);
  s.cameras.push_back(narrow_camera(t + V(kCentre, kCeilingY - 0.5f * gap, kCentre),
                                    V(0, 1, 0), V(0, 0, 1)));
  return s;
}

// Offsetting both ends of a shadow ray needs the gap to exceed the two offsets; below that the
// surfaces are too close for the float coordinates around them (at 1e4 a 1-unit gap is 1024
// ULPs). Tested from twice the two offsets up.
bool gap_resolvable(const Scene& s, float gap) {
  const V p = s.triangles[0].v0, n(0, 1, 0);
  return gap >= 2.0f * (offset_distance(p, n) + offset_distance(p - V(0, gap, 0), n));
}

// Before shadow rays were offset at both ends, the ceiling got no light from the square's upper
// face whenever the receiver's offset exceeded 0.1% of the gap: at shift 0 for gaps below
// 7.6e-3, at every gap here at shifts 1e2 and 1e4.
TEST_P(ClosedForm, EmitterCloseToReceiver) {
  const double expected = kCeilingAlbedo / kPi * irradiance_above_centre(1.0, 1.0, 1.0, 1.0);
  for (float gap : {1e-4f, 1e-3f, 1e-2f, 1e-1f, 1.0f}) {
    Estimate at_origin;
    for (float shift : {0.0f, 1e2f, 1e4f}) {
      const Scene scene = near_emitter_scene(gap, shift);
      if (!gap_resolvable(scene, gap)) {
        std::printf("gap %g shift %g: below the offsets' resolution, not tested\n", gap, shift);
        continue;
      }
      const Estimate e = estimate(render(scene, direct_only(16, 16), GetParam()).rgb);
      std::printf("gap %g shift %g: ceiling radiance %.5f +- %.5f, closed form %.5f\n", gap,
                  shift, e.mean, e.se, expected);
      EXPECT_NEAR(e.mean, expected, 4.0 * e.se + 1e-4) << "gap " << gap << " shift " << shift;
      EXPECT_LT(e.se, 0.02 * expected);  // the test can see a 10% error
      if (shift == 0.0f) at_origin = e;
      EXPECT_NEAR(e.mean, at_origin.mean, 4.0 * std::hypot(e.se, at_origin.se))
          << "translation changed the value: gap " << gap << " shift " << shift;
    }
  }
  expect_no_validation_messages();
}

// --- The Cornell box with its light hung below the ceiling ----------------------------------

constexpr float kCornellScale = 0.002f;  // millimetres → a box 1.1 units tall
constexpr std::size_t kCornellLight = 4;  // triangle ids 4 and 5 (builtin_cornell.cpp)

// builtin:cornell scaled to a 1.1-unit box, its (two-sided) light quad hung `gap` below the
// ceiling, moved up by `shift`. Camera 0: the classic view; camera 1: halfway in the gap above
// the light's centre, looking up at the ceiling.
Scene hanging_light_cornell(float gap, float shift) {
  Scene s = load_scene("builtin:cornell");
  const V up(0.0f, shift, 0.0f);
  const float ceiling = s.triangles[2].v0.y * kCornellScale;
  for (std::size_t i = 0; i < s.triangles.size(); ++i)
    for (V* v : {&s.triangles[i].v0, &s.triangles[i].v1, &s.triangles[i].v2}) {
      *v *= kCornellScale;
      if (i == kCornellLight || i == kCornellLight + 1) v->y = ceiling - gap;
      *v += up;
    }
  s.lights.clear();  // the area light's quad is sampled through its emissive triangles
  s.cameras[0].position = s.cameras[0].position * kCornellScale + up;
  const Triangle& l = s.triangles[kCornellLight];  // (c, c+u, c+u+v): v0 and v2 are opposite
  const V centre = 0.5f * (l.v0 + l.v2);
  s.cameras.push_back(narrow_camera(V(centre.x, ceiling - 0.5f * gap + shift, centre.z),
                                    V(0, 1, 0), V(0, 0, 1)));
  return s;
}

// Direct radiance of the ceiling above the light's centre, channels averaged.
double cornell_ceiling_closed_form(const Scene& s, float gap) {
  const Triangle& l = s.triangles[kCornellLight];
  const V extent = glm::abs(l.v2 - l.v0);
  const double e = irradiance_above_centre(1.0, 0.5 * extent.x, 0.5 * extent.z, gap);
  const V albedo = s.materials[s.shading[2].material].base_color;
  const V radiance = s.materials[s.shading[kCornellLight].material].emission;
  return e / kPi * glm::dot(albedo, radiance) / 3.0;
}

// The ceiling above the light as the gap shrinks, in the box as is and moved up by 99 units.
// Before the fix it was dark wherever the receiver's offset (256 ULPs: 3.05e-5 at y ≈ 1.1,
// 1.95e-3 at y ≈ 100) exceeded 0.1% of the gap: below 3.05 cm, and at every gap 99 units up.
TEST(LightTransport, CornellCeilingAboveHangingLightFadesInSmoothly) {
  for (float gap : {0.1f, 0.05f, 0.032f, 0.03f, 0.028f, 0.02f, 0.01f, 0.005f}) {
    for (float shift : {0.0f, 99.0f}) {
      const Scene scene = hanging_light_cornell(gap, shift);
      const float ceiling_y = scene.triangles[2].v0.y;
      const V n(0, 1, 0);
      if (gap < 2.0f * (offset_distance(V(0, ceiling_y, 0), n) +
                        offset_distance(V(0, ceiling_y - gap, 0), n))) {
        std::printf("gap %.3f shift %g: below the offsets' resolution, not tested\n", gap, shift);
        continue;
      }
      const double expected = cornell_ceiling_closed_form(scene, gap);
      const Estimate e = estimate(render(scene, direct_only(64, 16, 1)).rgb);
      std::printf("gap %.3f shift %g: ceiling above the light %.4f +- %.4f, closed form %.4f\n",
                  gap, shift, e.mean, e.se, expected);
      EXPECT_NEAR(e.mean, expected, 4.0 * e.se) << "gap " << gap << " shift " << shift;
      EXPECT_LT(e.se, 0.1 * expected);
    }
  }
  expect_no_validation_messages();
}

// The classic view of the box with the light 1 cm below the ceiling, full light transport:
// moving the box 99 units up changes nothing but the noise (before the fix its image was 15%
// darker there, and 20% darker at both places than after it). Pixels are clamped at 1, as in a
// PNG, so the rare bright samples of the ceiling next to the light do not drown the comparison.
// Light sampling alone: under MIS the estimator itself changes with the translation, as 99
// units up the offsets are 64x larger and light sampling alone takes the ceiling next to the
// light (bsdf_sees_light_at), with more of those bright samples.
TEST(LightTransport, CornellImageDoesNotChangeWhenTranslated) {
  RenderConfig config = direct_only(48, 16);
  config.max_depth = 5;
  config.light_sampling = LightSampling::kLight;
  std::vector<float> here = render(hanging_light_cornell(0.01f, 0.0f), config).rgb;
  std::vector<float> up = render(hanging_light_cornell(0.01f, 99.0f), config).rgb;
  std::vector<float> difference(here.size());
  for (std::size_t i = 0; i < here.size(); ++i) {
    here[i] = std::min(here[i], 1.0f);
    up[i] = std::min(up[i], 1.0f);
    difference[i] = up[i] - here[i];
  }
  const Estimate d = estimate(difference);
  std::printf("Cornell, light 1 cm below the ceiling: clamped image mean %.4f, 99 units up %.4f "
              "(difference %.4f +- %.4f)\n", estimate(here).mean, estimate(up).mean, d.mean, d.se);
  EXPECT_NEAR(d.mean, 0.0, 4.0 * d.se);
  EXPECT_LT(d.se, 0.02 * estimate(here).mean);  // the test can see a 10% change
  expect_no_validation_messages();
}

// --- Delta lights over a diffuse plane -------------------------------------------------------

constexpr float kFloorAlbedo = 0.5f;

// A diffuse floor (albedo 0.5, facing up, 4d × 4d) around point p = shift·(1, 1, 1) +
// (0.3, 0, 0.3) and `light`; with blocker_height > 0 a 0.1d × 0.1d square (albedo 0.5) on the
// line from p towards the light (`toward`, unit) at that height above the floor. The camera
// looks at p from p + (d, 2d, 0), past the blockers.
Scene delta_light_scene(Light light, float d, float shift, V toward, float blocker_height) {
  Scene s;
  s.name = "test:delta-light";
  const V p = V(shift) + V(0.3f, 0.0f, 0.3f);
  const std::uint32_t m = add_material(s, V(kFloorAlbedo));
  add_quad(s, p + V(-2 * d, 0, -2 * d), V(0, 0, 4 * d), V(4 * d, 0, 0), m);
  if (blocker_height > 0.0f) {
    const V c = p + toward * (blocker_height / toward.y);
    add_quad(s, c + V(-0.05f * d, 0, -0.05f * d), V(0, 0, 0.1f * d), V(0.1f * d, 0, 0), m);
  }
  light.position += p;
  s.lights.push_back(light);
  s.cameras.push_back(looking_at(p + V(d, 2 * d, 0), p, 0.004f));
  return s;
}

// Radiance of the floor point under the light (8 × 8 pixels, 1 sample: delta lights are not
// sampled at random).
double delta_light_radiance(Backend backend, const Light& light, float d, float shift, V toward,
                            float blocker_height = 0.0f) {
  return estimate(render(delta_light_scene(light, d, shift, toward, blocker_height),
                         direct_only(8, 1), backend).rgb).mean;
}

struct DeltaLightCase {
  const char* name;
  Light light;    // position relative to the floor point
  V toward;       // unit direction from the floor point to the light
  double cosine;  // of the light's direction at the floor
  bool has_position;
};

// Intensity I (point, spot) at height d over a diffuse floor of albedo ρ: radiance ρ I / (π d²)
// under it; directional irradiance E: ρ E cos θ / π (docs/RENDERER.md).
std::vector<DeltaLightCase> delta_light_cases(float d) {
  Light point;
  point.type = LightType::kPoint;
  point.color = V(3.0f);
  point.position = V(0, d, 0);
  Light spot = point;
  spot.type = LightType::kSpot;
  spot.direction = V(0, -1, 0);
  spot.inner_cone = 0.2f;
  spot.outer_cone = 0.4f;
  Light sun;
  sun.type = LightType::kDirectional;
  sun.color = V(2.0f);
  sun.direction = V(0, -1, 0);
  Light tilted = sun;
  tilted.direction = glm::normalize(V(0, -1, 1));
  const double c45 = std::sqrt(0.5);
  return {{"point", point, V(0, 1, 0), 1.0, true},
          {"spot", spot, V(0, 1, 0), 1.0, true},
          {"directional", sun, V(0, 1, 0), 1.0, false},
          {"tilted directional", tilted, -tilted.direction, c45, false}};
}

// A blocker halfway darkens the point completely; for point and spot lights one 1% of d short
// of the light does too and one 1% beyond it does not (the shadow ray ends at the light).
// Heights d from 1e-2 to 1e2, the scene translated by 0, 1e2 and 1e4 where the receiver's
// offset is under 0.5% of d.
TEST_P(ClosedForm, DeltaLightsOverDiffusePlane) {
  const Backend b = GetParam();
  for (float d : {1e-2f, 1.0f, 1e2f}) {
    for (float shift : {0.0f, 1e2f, 1e4f}) {
      const V p = V(shift) + V(0.3f, 0.0f, 0.3f);
      if (0.01f * d < 2.0f * offset_distance(p, V(0, 1, 0))) continue;
      for (const DeltaLightCase& c : delta_light_cases(d)) {
        const double power = c.has_position ? 3.0 / (double(d) * d) : 2.0 * c.cosine;
        const double expected = kFloorAlbedo * power / kPi;
        const std::string where = std::string(c.name) + " d " + std::to_string(d) + " shift " +
                                  std::to_string(shift);
        EXPECT_NEAR(delta_light_radiance(b, c.light, d, shift, c.toward), expected, 2e-4 * expected)
            << where;
        EXPECT_EQ(delta_light_radiance(b, c.light, d, shift, c.toward, 0.5f * d * c.toward.y), 0.0)
            << where << ": blocker halfway";
        if (!c.has_position || c.light.type == LightType::kSpot) continue;
        EXPECT_EQ(delta_light_radiance(b, c.light, d, shift, c.toward, 0.99f * d), 0.0)
            << where << ": blocker just short of the light";
        EXPECT_NEAR(delta_light_radiance(b, c.light, d, shift, c.toward, 1.01f * d), expected,
                    2e-4 * expected) << where << ": blocker just beyond the light";
      }
    }
  }
  expect_no_validation_messages();
}

// --- A diffuse convex body in a constant environment ---------------------------------------

// Flat-faced sphere (an icosahedron subdivided twice, 320 faces) of radius 1 around c.
void add_polyhedron(Scene& s, V c, std::uint32_t material) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<V> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                      {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<glm::uvec3> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                               {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                               {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                               {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (V& x : v) x = glm::normalize(x);
  for (int level = 0; level < 2; ++level) {
    std::vector<glm::uvec3> finer;
    for (const glm::uvec3& tri : f) {
      std::uint32_t mid[3];
      for (int e = 0; e < 3; ++e) {
        v.push_back(glm::normalize(v[tri[e]] + v[tri[(e + 1) % 3]]));
        mid[e] = static_cast<std::uint32_t>(v.size() - 1);
      }
      finer.push_back({tri[0], mid[0], mid[2]});
      finer.push_back({tri[1], mid[1], mid[0]});
      finer.push_back({tri[2], mid[2], mid[1]});
      finer.push_back({mid[0], mid[1], mid[2]});
    }
    f = finer;
  }
  for (const glm::uvec3& tri : f) {
    s.triangles.push_back(Triangle{c + v[tri[0]], c + v[tri[1]], c + v[tri[2]]});
    TriangleShading sh;
    sh.material = material;
    s.shading.push_back(sh);
  }
}

// Seen from outside, a convex diffuse body of albedo ρ in a constant environment L reflects
// exactly ρ L: every bounce off it escapes. With one sample per pixel and two interactions a
// pixel is L (background) or ρ L (body), nothing else; a bounce ray that hit the body again
// (self-intersection at an edge or vertex of the facets) would give 0.
TEST_P(ClosedForm, FurnaceConvexBodyInEnvironment) {
  const float albedo = 0.3f, environment = 0.5f;
  for (float shift : {0.0f, 1e2f, 1e4f}) {
    Scene scene;
    scene.name = "test:convex-body";
    const V c(shift);
    add_polyhedron(scene, c, add_material(scene, V(albedo)));
    Light env;
    env.type = LightType::kEnvironment;
    env.color = V(environment);
    scene.lights.push_back(env);
    scene.cameras.push_back(looking_at(c + V(0.8f, 1.2f, 3.2f), c, 0.7f));
    RenderConfig config = direct_only(48, 1);
    config.max_depth = 2;
    const RenderResult r = render(scene, config, GetParam());
    std::size_t body = 0, other = 0;
    for (float v : r.rgb) {
      if (v == environment * albedo) ++body;
      else if (v != environment) ++other;
    }
    EXPECT_EQ(other, 0u) << "shift " << shift << ": pixels neither L nor the body's ρ L";
    EXPECT_GT(body, r.rgb.size() / 4) << "shift " << shift;  // the body fills the view's middle
    EXPECT_EQ(r.stats.shadow().counters.rays, 0u);
  }
  expect_no_validation_messages();
}

// --- Fresnel at normal incidence on a smooth dielectric ------------------------------------

// A black smooth dielectric (roughness 0: its specular layer a mirror) seen head-on in a constant
// environment L reflects Schlick's f0 = ((ior - 1) / (ior + 1))² times specularFactor of it, and
// its diffuse nothing: 0.04 L for ior 1.5, L / 9 for ior 2, exactly 0 without a layer. Each
// sample reflects f0 / p or 0 (the layer is picked with probability p), so the mean is tested.
TEST_P(ClosedForm, SmoothDielectricReflectsF0AtNormalIncidence) {
  const float environment = 0.5f;
  for (const auto& [ior, specular] :
       {std::pair{1.5f, 1.0f}, std::pair{2.0f, 1.0f}, std::pair{1.5f, 0.0f}}) {
    Scene scene;
    scene.name = "test:smooth-dielectric";
    Material m;
    m.base_color = V(0.0f);
    m.roughness = 0.0f;
    m.ior = ior;
    m.specular = specular;
    scene.materials.push_back(m);
    add_quad(scene, V(-1, -1, 0), V(2, 0, 0), V(0, 2, 0), 0);
    Light env;
    env.type = LightType::kEnvironment;
    env.color = V(environment);
    scene.lights.push_back(env);
    scene.cameras.push_back(narrow_camera(V(0, 0, 3), V(0, 0, -1), V(0, 1, 0)));
    RenderConfig config = direct_only(16, 64);
    config.max_depth = 2;
    const Estimate e = estimate(render(scene, config, GetParam()).rgb);
    const double r = (ior - 1.0) / (ior + 1.0);
    const double want = r * r * specular * environment;
    EXPECT_NEAR(e.mean, want, 0.01 * want) << "ior " << ior << " specular " << specular;
  }
  expect_no_validation_messages();
}

// A 1 × 1 texture of one RGBA8 texel.
Texture one_texel(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Texture t;
  t.width = t.height = 1;
  t.rgba = {r, g, b, 255};
  return t;
}

// glTF's metallicRoughnessTexture scales metallic by its B channel and roughness by its G. The
// factors metallic 1, roughness 1 (a rough metal) under the texel (0, 0, 255) make a mirror,
// which seen at 60° from its normal in a constant environment L reflects Schlick's
// F = c + (1 - c)(1 - cos 60°)⁵ of it; under (0, 255, 0) a Lambertian diffuse, which reflects
// c L (every sample's weight is c: both are exact per sample).
TEST_P(ClosedForm, MetallicRoughnessTextureScalesTheFactors) {
  const float environment = 0.5f, c = 0.2f;
  const double mirror = c + (1.0 - c) * std::pow(0.5, 5.0);
  for (const auto& [g, b, want] : {std::tuple{0, 255, mirror}, std::tuple{255, 0, double(c)}}) {
    Scene scene;
    scene.name = "test:metallic-roughness-texture";
    scene.textures.push_back(one_texel(0, static_cast<std::uint8_t>(g),
                                       static_cast<std::uint8_t>(b)));
    Material m;
    m.base_color = V(c);
    m.metallic = 1.0f;
    m.roughness = 1.0f;
    m.metallic_roughness_texture = 0;
    scene.materials.push_back(m);
    add_quad(scene, V(-1, -1, 0), V(2, 0, 0), V(0, 2, 0), 0);
    Light env;
    env.type = LightType::kEnvironment;
    env.color = V(environment);
    scene.lights.push_back(env);
    const V eye = 3.0f * V(0.0f, -std::sin(kPi / 3.0), std::cos(kPi / 3.0));
    scene.cameras.push_back(narrow_camera(eye, -glm::normalize(eye), V(0, 0, 1)));
    RenderConfig config = direct_only(16, 16);
    config.max_depth = 2;
    const Estimate e = estimate(render(scene, config, GetParam()).rgb);
    EXPECT_NEAR(e.mean, want * environment, 2e-3 * want) << "texel G " << g << " B " << b;
  }
  expect_no_validation_messages();
}

// glTF's emissiveTexture (sRGB-encoded) scales emissiveFactor: a texel of 188 decodes to
// ((188/255 + 0.055)/1.055)^2.4 (0.737 if it were read as linear), so a factor of its inverse
// makes radiance 1. A triangle with an emissive texture is no light sample's target; the
// ceiling above the textured square is lit through its BSDF samples alone, to the closed form
// of EmitterCloseToReceiver, and a camera looking down sees radiance 1.
TEST_P(ClosedForm, EmissiveTextureScalesEmission) {
  const double texel = std::pow((188.0 / 255.0 + 0.055) / 1.055, 2.4);
  const float gap = 0.1f;
  Scene scene = near_emitter_scene(gap, 0.0f);
  scene.textures.push_back(one_texel(188, 188, 188));
  scene.materials[1].emission = V(static_cast<float>(1.0 / texel));
  scene.materials[1].emissive_texture = 0;
  scene.cameras.push_back(narrow_camera(V(kCentre, kCeilingY - 0.5f * gap, kCentre), V(0, -1, 0),
                                        V(0, 0, 1)));
  RenderConfig config = direct_only(16, 64);
  config.max_depth = 2;
  const Estimate ceiling = estimate(render(scene, config, GetParam()).rgb);
  const double expected = kCeilingAlbedo / kPi * irradiance_above_centre(1.0, gap, gap, gap);
  EXPECT_NEAR(ceiling.mean, expected, 4.0 * ceiling.se + 1e-4);
  EXPECT_LT(ceiling.se, 0.02 * expected);
  config.camera = 1;
  const Estimate square = estimate(render(scene, config, GetParam()).rgb);
  EXPECT_NEAR(square.mean, 1.0, 1e-3);
  expect_no_validation_messages();
}

INSTANTIATE_TEST_SUITE_P(Backends, ClosedForm, testing::Values(Backend::kDevice, Backend::kCpu),
                         backend_name);

// --- The shadow-ray construction on the device equals its C++ mirror ------------------------

std::vector<gpu::OffsetRayCase> offset_ray_cases() {
  const float one_32 = 1.0f / 32.0f;
  const std::vector<float> edges = {0.0f, -0.0f, 1e-30f, std::bit_cast<float>(1u), one_32,
                                    std::nextafter(one_32, 0.0f), -one_32, 0.5f, -0.5f, 1.0f,
                                    1.0976f, 100.5f, -1e4f, 1e4f + 0.3f, 3e38f};
  const std::vector<V> normals = {V(1, 0, 0), V(0, -1, 0), V(0, 0, 1), V(0.0f),
                                  glm::normalize(V(1, -2, 3)), glm::normalize(V(-1, 1, 1))};
  std::vector<gpu::OffsetRayCase> cases;
  const auto add = [&](V p, V n, V q, V nq) {
    cases.push_back({glm::vec4(p, 0), glm::vec4(n, 0), glm::vec4(q, 0), glm::vec4(nq, 0)});
  };
  for (float e : edges)
    for (const V& n : normals) {
      add(V(e, 0.25f, -0.75f), n, V(0.5f, e, 2.0f), -n);
      add(V(-1.5f, e, e), n, V(e, -e, 0.0f), V(0.0f));
      add(V(e), n, V(e), n);  // p = q: zero length
    }
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_int_distribution<int> exponent(-6, 4);
  for (int i = 0; i < 20000; ++i) {
    const float scale = std::pow(10.0f, static_cast<float>(exponent(rng)));
    const V p = scale * V(unit(rng), unit(rng), unit(rng));
    const V q = p + scale * 1e-2f * V(unit(rng), unit(rng), unit(rng));
    const V n = glm::normalize(V(unit(rng), unit(rng), unit(rng)));
    add(p, n, q, i % 4 == 0 ? V(0.0f) : glm::normalize(V(unit(rng), unit(rng), unit(rng))));
  }
  return cases;
}

std::vector<gpu::OffsetRayResult> offset_rays_on_device(
    const std::vector<gpu::OffsetRayCase>& cases) {
  VulkanContext& ctx = context();
  StorageBuffer in(ctx, cases.size() * sizeof(gpu::OffsetRayCase), "offset ray cases");
  StorageBuffer out(ctx, cases.size() * sizeof(gpu::OffsetRayResult), "offset ray results");
  in.upload(std::span<const gpu::OffsetRayCase>(cases));
  out.fill(0xFFFFFFFFu);
  ComputePipeline p(ctx, Kernel::render_offset_rays, embedded_spirv(Kernel::render_offset_rays),
                    HRPP_OFFSET_RAYS_BINDING_COUNT, sizeof(std::uint32_t));
  p.bind(HRPP_OFFSET_RAYS_BINDING_CASES, in);
  p.bind(HRPP_OFFSET_RAYS_BINDING_RESULTS, out);
  const auto count = static_cast<std::uint32_t>(cases.size());
  const std::uint32_t groups = (count + HRPP_RENDER_WORKGROUP_SIZE - 1) / HRPP_RENDER_WORKGROUP_SIZE;
  ctx.submit_and_wait([&](VkCommandBuffer cmd) { record_dispatch(cmd, p, &count, groups, nullptr); },
                      p.name());
  std::vector<gpu::OffsetRayResult> results(cases.size());
  out.download(std::span<gpu::OffsetRayResult>(results));
  return results;
}

bool same_bits(const float* a, const float* b, int n) {
  for (int i = 0; i < n; ++i)
    if (std::bit_cast<std::uint32_t>(a[i]) != std::bit_cast<std::uint32_t>(b[i])) return false;
  return true;
}

float flushed(float x) { return std::fpclassify(x) == FP_SUBNORMAL ? std::copysign(0.0f, x) : x; }
V flushed(V v) { return V(flushed(v.x), flushed(v.y), flushed(v.z)); }
bool has_subnormal(const gpu::OffsetRayCase& c) {
  for (const glm::vec4& v : {c.p, c.n, c.q, c.nq})
    for (int i = 0; i < 3; ++i)
      if (std::fpclassify(v[i]) == FP_SUBNORMAL) return true;
  return false;
}

// The mirror's answer: the offset origin and the shadow ray, with every input and output
// subnormal flushed to zero when `flush` (a device that flushes float denormals: Vulkan allows
// it where the device does not report shaderDenormPreserveFloat32).
struct Mirror {
  V origin;
  gpu::Ray shadow;
};
Mirror mirror(const gpu::OffsetRayCase& c, bool flush) {
  const auto in = [&](const glm::vec4& v) { return flush ? flushed(V(v)) : V(v); };
  Mirror m{offset_ray_origin(in(c.p), in(c.n)), shadow_ray_to(in(c.p), in(c.n), in(c.q), in(c.nq))};
  if (flush) {
    m.origin = flushed(m.origin);
    float* f = &m.shadow.origin.x;  // the ray's 8 floats, as same_bits reads them
    for (int i = 0; i < 8; ++i) f[i] = flushed(f[i]);
  }
  return m;
}

bool equals(const Mirror& m, const gpu::OffsetRayResult& g) {
  return same_bits(&m.origin.x, &g.origin.x, 3) &&
         same_bits(&m.shadow.origin.x, &g.shadow.origin.x, 8);
}

// Bit for bit; on a device that may flush denormals, a case with a subnormal input may instead
// equal the mirror on flushed inputs and outputs (counted and printed).
TEST(LightTransport, OffsetRaysOnDeviceEqualTheMirrorBitForBit) {
  const std::vector<gpu::OffsetRayCase> cases = offset_ray_cases();
  const std::vector<gpu::OffsetRayResult> gpu_results = offset_rays_on_device(cases);
  const bool may_flush = !context().info().denorm_preserve;
  int mismatches = 0, flushed_cases = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const gpu::OffsetRayCase& c = cases[i];
    const gpu::OffsetRayResult& g = gpu_results[i];
    const Mirror exact = mirror(c, false);
    if (equals(exact, g)) continue;
    if (may_flush && has_subnormal(c) && equals(mirror(c, true), g)) {
      ++flushed_cases;
      continue;
    }
    const gpu::Ray& shadow = exact.shadow;
    if (++mismatches <= 5)
      ADD_FAILURE() << "case " << i << ": p (" << c.p.x << ", " << c.p.y << ", " << c.p.z
                    << ") q (" << c.q.x << ", " << c.q.y << ", " << c.q.z << "): C++ dir ("
                    << shadow.dir.x << ", " << shadow.dir.y << ", " << shadow.dir.z << ") tmax "
                    << shadow.tmax << ", device dir (" << g.shadow.dir.x << ", "
                    << g.shadow.dir.y << ", " << g.shadow.dir.z << ") tmax " << g.shadow.tmax;
  }
  std::printf("%zu cases: %d equal the mirror only with subnormals flushed (the device %s)\n",
              cases.size(), flushed_cases,
              may_flush ? "may flush them" : "keeps them: none may differ");
  EXPECT_EQ(mismatches, 0) << "of " << cases.size() << " cases";
  expect_no_validation_messages();
}

}  // namespace
}  // namespace hrpp
