// OBJ (with its MTL materials) and PLY files, read through assimp (docs/FORMATS.md, "OBJ and
// PLY"): polygons triangulated, materials mapped onto hrpp's Material, texture files decoded.
#pragma once

#include <filesystem>
#include <string>

#include "scene/indexed_mesh.h"
#include "scene/scene.h"

namespace hrpp {

// A whole .obj or .ply file as a Scene in the file's own coordinates (no camera or lights:
// load_scene adds the defaults). Throws hrpp::Error with one line naming the file.
Scene load_mesh_file(const std::filesystem::path& file);

// A PLY file as one mesh (pbrt's `plymesh`): positions, normals and uvs when present, every
// face triangulated. Throws hrpp::Error naming `where` and the file.
IndexedMesh read_ply_mesh(const std::filesystem::path& file, const std::string& where);

}  // namespace hrpp
