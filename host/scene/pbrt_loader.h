// pbrt-v4 scene files (*.pbrt): the directives, shapes, lights and materials that scenes use,
// flattened into one Scene (docs/FORMATS.md, "pbrt-v4"). Geometry it cannot read is an error
// naming file, line and directive; a material or light feature it does not support is one
// warning line, and the scene loads.
#pragma once

#include <filesystem>

#include "scene/scene.h"

namespace hrpp {

Scene load_pbrt(const std::filesystem::path& file);

}  // namespace hrpp
