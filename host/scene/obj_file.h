// Wavefront OBJ files (with their MTL materials) through tinyobjloader's streaming reader
// (docs/FORMATS.md, "OBJ and PLY"): each face goes straight into the Scene, so the file's
// vertex lists are the only copy held beside it.
#pragma once

#include <filesystem>

#include "scene/scene.h"

namespace hrpp {

// The file's triangles in face order, polygons triangulated (a fan where the polygon is convex,
// ear clipping where it is not). Throws hrpp::Error "<file>:<line>: ..." on a bad face or
// vertex, "<file>: ..." otherwise.
Scene load_obj_file(const std::filesystem::path& file);

}  // namespace hrpp
