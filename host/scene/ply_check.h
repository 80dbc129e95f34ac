// A PLY file's structure checked before assimp reads it: the header, and that the body holds
// every element the header declares (assimp reads past the end of a truncated binary file, and
// makes triangles up from a truncated ASCII one). Faces of fewer than three vertices are refused
// here too, where the face element's own lists are visible.
#pragma once

#include <filesystem>

namespace hrpp {

// Throws hrpp::Error "<file>: ..." (one line) on a malformed or truncated file.
void check_ply_file(const std::filesystem::path& file);

}  // namespace hrpp
