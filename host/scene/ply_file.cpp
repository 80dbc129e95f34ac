// PLY through assimp (ply_file.h). The file's structure is checked first (ply_check.h: assimp
// reads past the end of a truncated binary file); assimp parses and triangulates; its meshes
// are copied into one IndexedMesh and assimp's copy freed before the Scene is built, so the
// two are never held at once.
#include "scene/ply_file.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <string>
#include <vector>

#include "common/error.h"
#include "scene/ply_check.h"
#include "scene/scene_builder.h"

namespace hrpp {
namespace {

// Triangulate: polygons to triangles (assimp's: a quad as a fan from a concave corner, larger
// polygons by ear clipping). SortByPType: points and lines apart. FlipUVs: v from PLY's
// bottom-up to glTF's top-down texture rows.
constexpr unsigned kImportFlags = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_FlipUVs;

std::string one_line(std::string s) {
  for (char& c : s) {
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

void append_vertices(IndexedMesh& out, const aiMesh& m, const std::string& where) {
  const bool first = out.positions.empty();
  if (!first &&
      (out.normals.empty() == m.HasNormals() || out.uvs.empty() == m.HasTextureCoords(0))) {
    throw Error(where + ": its meshes differ in their vertex attributes");
  }
  for (unsigned v = 0; v < m.mNumVertices; ++v) {
    out.positions.emplace_back(m.mVertices[v].x, m.mVertices[v].y, m.mVertices[v].z);
    if (m.HasNormals()) out.normals.emplace_back(m.mNormals[v].x, m.mNormals[v].y, m.mNormals[v].z);
    if (m.HasTextureCoords(0))
      out.uvs.emplace_back(m.mTextureCoords[0][v].x, m.mTextureCoords[0][v].y);
  }
}

void append_faces(IndexedMesh& out, const aiMesh& m, std::uint32_t base, const std::string& where) {
  for (unsigned f = 0; f < m.mNumFaces; ++f) {
    const aiFace& face = m.mFaces[f];
    if (face.mNumIndices != 3) {
      throw Error(where + ": face " + std::to_string(f) + " has fewer than three vertices");
    }
    for (unsigned k = 0; k < 3; ++k) out.indices.push_back(base + face.mIndices[k]);
  }
}

IndexedMesh read(const std::filesystem::path& file, const std::string& where) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw Error(where + ": no such file");
  if (std::filesystem::is_directory(file, ec)) throw Error(where + ": is a directory");
  check_ply_file(file);
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, 0);
  const aiScene* s = importer.ReadFile(file.string(), kImportFlags);
  if (s == nullptr) throw Error(one_line(where + ": " + importer.GetErrorString()));
  IndexedMesh out;
  for (unsigned i = 0; i < s->mNumMeshes; ++i) {
    const aiMesh& m = *s->mMeshes[i];
    if (!(m.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;  // points or lines
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    append_vertices(out, m, where);
    append_faces(out, m, base, where);
  }
  check_mesh(out, where);
  return out;
}

}  // namespace

Scene load_ply_file(const std::filesystem::path& file) {
  IndexedMesh mesh = read(file, file.string());  // assimp's scene is gone here
  Scene scene;
  scene.name = file.filename().string();
  scene.materials.push_back(Material{"default"});
  scene.triangles.reserve(mesh.triangle_count());
  scene.shading.reserve(mesh.triangle_count());
  append_mesh(scene, mesh, MeshPlacement{}, file.string());
  return scene;
}

IndexedMesh read_ply_mesh(const std::filesystem::path& file, const std::string& where) {
  try {
    return read(file, file.string());
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
}

}  // namespace hrpp
