#include "hrpp/ray_class.h"

#include <string>

#include "common/error.h"

namespace hrpp {

const char* ray_class_name(RayClass c) {
  switch (c) {
    case RayClass::kCamera: return "camera";
    case RayClass::kBounce: return "bounce";
    case RayClass::kShadow: return "shadow";
  }
  return "?";
}

RayClass parse_ray_class(std::string_view name) {
  for (RayClass c : kRayClasses)
    if (name == ray_class_name(c)) return c;
  throw Error("'" + std::string(name) + "' is not a ray class (camera, bounce, shadow)");
}

}  // namespace hrpp
