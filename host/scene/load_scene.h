// Entry point of the scene stage: turns a scene name on the command line into a Scene.
#pragma once

#include <filesystem>
#include <string>

#include "scene/scene.h"

namespace hrpp {

// SCENE may be:
//   builtin:cornell            the classic Cornell box (the default scene)
//   path/to/file.gltf|.glb     a glTF 2.0 file
//   path/to/file.scene.json    a scene manifest (see scenes/README.md)
//   NAME                       scenes/NAME.scene.json of this source tree (e.g. "bunny")
// Throws hrpp::Error with a one-line message naming the file on any problem, including a scene
// without triangles. Adds a default camera (framing the bounds) when the scene has none.
Scene load_scene(const std::string& spec);

// The individual loaders (all throw hrpp::Error).
Scene load_gltf(const std::filesystem::path& file);
Scene load_manifest(const std::filesystem::path& file);
Scene builtin_cornell();

// True when the triangle has zero area (repeated or collinear vertices). Such triangles keep
// their ids but never enter the BVH.
bool is_degenerate(const Triangle& t);

// Triangle dump (docs/FORMATS.md): 9 × float32 per triangle (v0, v1, v2), little-endian,
// triangle-id order.
void write_triangle_dump(const Scene& scene, const std::filesystem::path& file);

}  // namespace hrpp
