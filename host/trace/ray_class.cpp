#include "trace/ray_class.h"

#include <string>

#include "common/error.h"

namespace hrpp {

RayClass parse_ray_class(std::string_view name) {
  return parse_in(kRayClassNames, name, "unknown ray class");
}

}  // namespace hrpp
