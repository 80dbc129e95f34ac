#include "hrpp/ray_class.h"

#include <string>

#include "common/error.h"

namespace hrpp {

RayClass parse_ray_class(std::string_view name) {
  for (const Named<RayClass>& n : kRayClassNames)
    if (name == n.name) return n.value;
  throw Error("'" + std::string(name) + "' is not a ray class (" + names_in(kRayClassNames) + ")");
}

}  // namespace hrpp
