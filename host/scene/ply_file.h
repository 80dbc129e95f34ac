// PLY files (Greg Turk's polygon format: the Stanford scans, pbrt's plymesh) through assimp
// (docs/FORMATS.md, "OBJ and PLY"), its structure checked first (ply_check.h).
#pragma once

#include <filesystem>
#include <string>

#include "scene/indexed_mesh.h"
#include "scene/scene.h"

namespace hrpp {

// A whole .ply file as a Scene of one default material, in the file's own coordinates (no
// camera or lights: load_scene adds the defaults). Throws hrpp::Error with one line naming the
// file.
Scene load_ply_file(const std::filesystem::path& file);

// The file as one mesh (pbrt's `plymesh`): positions, normals and uvs when present, every face
// triangulated, uv's v flipped to glTF's top-down rows. Throws hrpp::Error naming `where`.
IndexedMesh read_ply_mesh(const std::filesystem::path& file, const std::string& where);

}  // namespace hrpp
