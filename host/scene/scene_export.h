// The scene as loaded, as JSON for another renderer: study/cycles_reference.py builds the same
// scene in Blender's Cycles from it to compare hrpp render against (docs/FORMATS.md, "Scene
// export"). Every triangle's positions and vertex normals (9 floats each, id order; zero
// normals: none) and material index, the
// materials, the lights and the cameras, in the loaders' units and axes. Textures are not
// exported: a material says whether it had one.
#pragma once

#include <string>

#include "scene/scene.h"

namespace hrpp {

std::string scene_json(const Scene& scene);

}  // namespace hrpp
