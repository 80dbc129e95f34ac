// Ray classes: camera, bounce and shadow rays. Each has its own predictor table, switch,
// counters and kernel times (shaders/shared/hrpp_types.h, HRPP_RAY_CLASS_*). A new class is one
// value there and here, plus the place that produces its rays (docs/HRPP.md, "Adding a hash / a
// replacement policy / a ray class / a counter / a backend").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/name_table.h"
#include "hrpp_types.h"
#include "trace/query_kind.h"

namespace hrpp {

enum class RayClass : std::uint32_t {
  kCamera = HRPP_RAY_CLASS_CAMERA,  // closest hit, from render_generate (or a ray file)
  kBounce = HRPP_RAY_CLASS_BOUNCE,  // closest hit, continuation rays from render_shade
  kShadow = HRPP_RAY_CLASS_SHADOW,  // any hit, toward a sampled light
};

inline constexpr std::size_t kRayClassCount = HRPP_RAY_CLASS_COUNT;
inline constexpr std::array<RayClass, kRayClassCount> kRayClasses = {
    RayClass::kCamera, RayClass::kBounce, RayClass::kShadow};

inline constexpr NameTable<RayClass, kRayClassCount> kRayClassNames = {
    {{RayClass::kCamera, "camera"}, {RayClass::kBounce, "bounce"}, {RayClass::kShadow, "shadow"}}};

constexpr std::size_t index_of(RayClass c) { return static_cast<std::size_t>(c); }
// Shadow rays are hit-any (occlusion) queries: the first hit found answers them.
constexpr QueryKind query_kind(RayClass c) {
  return c == RayClass::kShadow ? QueryKind::kAny : QueryKind::kClosest;
}
// Rays of a ray file (hrpp trace, hrpp bench): closest-hit rays are traced as camera rays,
// any-hit rays as shadow rays.
constexpr RayClass ray_file_class(QueryKind k) {
  return k == QueryKind::kAny ? RayClass::kShadow : RayClass::kCamera;
}

constexpr const char* ray_class_name(RayClass c) { return name_in(kRayClassNames, c); }
// Throws hrpp::Error for an unknown name.
RayClass parse_ray_class(std::string_view name);

// A value per ray class.
template <class T>
struct PerClass {
  std::array<T, kRayClassCount> v{};
  T& operator[](RayClass c) { return v[index_of(c)]; }
  const T& operator[](RayClass c) const { return v[index_of(c)]; }
};

}  // namespace hrpp
