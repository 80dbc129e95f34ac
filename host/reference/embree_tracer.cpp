#include "reference/embree_tracer.h"

#include <chrono>
#include <limits>

#include "common/error.h"
#include "scene/load_scene.h"
#include "trace/ray_batches.h"

#ifdef HRPP_HAVE_EMBREE
#include "reference/embree_api.h"
#endif

namespace hrpp {

#ifdef HRPP_HAVE_EMBREE

namespace {

void check_device(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE)
    throw Error(std::string("Embree: ") + what + " failed (RTCError " + std::to_string(e) + ")");
}

}  // namespace

struct EmbreeTracer::State {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<int> prim_of;  // Embree primID → triangle id
  double build_ms = 0.0;

  ~State() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

bool embree_available() { return true; }

std::string embree_version() {
  return "Embree " + std::to_string(RTC_VERSION_MAJOR) + "." + std::to_string(RTC_VERSION_MINOR) +
         "." + std::to_string(RTC_VERSION_PATCH);
}

EmbreeTracer::EmbreeTracer(const Scene& scene) : s_(std::make_unique<State>()) {
  s_->device = rtcNewDevice(nullptr);
  if (!s_->device) throw Error("Embree: rtcNewDevice failed");
  for (std::size_t i = 0; i < scene.triangles.size(); ++i)
    if (!is_degenerate(scene.triangles[i])) s_->prim_of.push_back(static_cast<int>(i));
  const std::size_t n = s_->prim_of.size();

  RTCGeometry geom = rtcNewGeometry(s_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  check_device(s_->device, "rtcNewGeometry");
  // Three unshared vertices per triangle: exactly the coordinates the other tracers test.
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geom);
    check_device(s_->device, "rtcSetNewGeometryBuffer");
    throw Error("Embree: rtcSetNewGeometryBuffer failed");
  }
  for (std::size_t k = 0; k < n; ++k) {
    const Triangle& t = scene.triangles[static_cast<std::size_t>(s_->prim_of[k])];
    const glm::vec3 v[3] = {t.v0, t.v1, t.v2};
    for (int j = 0; j < 3; ++j) {
      vertices[9 * k + 3 * j + 0] = v[j].x;
      vertices[9 * k + 3 * j + 1] = v[j].y;
      vertices[9 * k + 3 * j + 2] = v[j].z;
      indices[3 * k + j] = static_cast<unsigned>(3 * k + j);
    }
  }
  rtcCommitGeometry(geom);
  s_->scene = rtcNewScene(s_->device);
  // As Embree's users build for correctness-sensitive work: high quality and robust traversal
  // (no misses through shared edges), the configuration the GPU/Embree ratios compare with.
  rtcSetSceneBuildQuality(s_->scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(s_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcAttachGeometry(s_->scene, geom);
  rtcReleaseGeometry(geom);
  const auto start = std::chrono::steady_clock::now();
  rtcCommitScene(s_->scene);
  s_->build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  check_device(s_->device, "building the scene");
}

EmbreeTracer::~EmbreeTracer() = default;
EmbreeTracer::EmbreeTracer(EmbreeTracer&&) noexcept = default;
EmbreeTracer& EmbreeTracer::operator=(EmbreeTracer&&) noexcept = default;

namespace {

RTCRay to_embree(const gpu::Ray& r) {
  RTCRay e{};
  e.org_x = r.origin.x;
  e.org_y = r.origin.y;
  e.org_z = r.origin.z;
  e.tnear = r.tmin;
  e.dir_x = r.dir.x;
  e.dir_y = r.dir.y;
  e.dir_z = r.dir.z;
  e.tfar = r.tmax;
  e.time = 0.0f;
  e.mask = 0xffffffffu;
  e.id = 0;
  e.flags = 0;
  return e;
}

}  // namespace

gpu::Hit EmbreeTracer::closest(const gpu::Ray& ray) const {
  RTCRayHit rh{};
  rh.ray = to_embree(ray);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  embree::intersect1(s_->scene, rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {-1, 0.0f, 0.0f, 0.0f};
  return {s_->prim_of[rh.hit.primID], rh.ray.tfar, rh.hit.u, rh.hit.v};
}

bool EmbreeTracer::occluded(const gpu::Ray& ray) const {
  RTCRay r = to_embree(ray);
  embree::occluded1(s_->scene, r);
  return r.tfar < 0.0f;  // Embree sets tfar = -inf when something blocks the ray
}

double EmbreeTracer::build_ms() const { return s_->build_ms; }

#else  // !HRPP_HAVE_EMBREE

struct EmbreeTracer::State {};

bool embree_available() { return false; }
std::string embree_version() { return "Embree not available"; }

EmbreeTracer::EmbreeTracer(const Scene&) {
  throw Error("Embree not available: this build has no Embree (HRPP_WITH_EMBREE, libembree-dev)");
}
EmbreeTracer::~EmbreeTracer() = default;
EmbreeTracer::EmbreeTracer(EmbreeTracer&&) noexcept = default;
EmbreeTracer& EmbreeTracer::operator=(EmbreeTracer&&) noexcept = default;
gpu::Hit EmbreeTracer::closest(const gpu::Ray&) const { return {-1, 0.0f, 0.0f, 0.0f}; }
bool EmbreeTracer::occluded(const gpu::Ray&) const { return false; }
double EmbreeTracer::build_ms() const { return 0.0; }

#endif  // HRPP_HAVE_EMBREE

std::vector<gpu::Hit> EmbreeTracer::trace(std::span<const gpu::Ray> rays, QueryKind kind,
                                          int threads) const {
  std::vector<gpu::Hit> hits(rays.size());
  trace(rays, kind, hits, threads);
  return hits;
}

void EmbreeTracer::trace(std::span<const gpu::Ray> rays, QueryKind kind, std::span<gpu::Hit> hits,
                         int threads) const {
  parallel_ranges(rays.size(), threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      hits[i] = kind == QueryKind::kAny ? (occluded(rays[i]) ? gpu::Hit{0, 0.0f, 0.0f, 0.0f}
                                                             : gpu::Hit{-1, 0.0f, 0.0f, 0.0f})
                                        : closest(rays[i]);
  });
}

}  // namespace hrpp
