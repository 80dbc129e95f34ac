// OBJ and PLY through assimp (mesh_file.h). assimp parses and triangulates; this file checks
// what it hands over (finite positions, indices in range, faces of three or more vertices),
// maps MTL materials (mtl_material.h) and flattens the node tree in its order.
#include "scene/mesh_file.h"

#include <assimp/ObjMaterial.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "common/error.h"
#include "scene/mtl_material.h"
#include "scene/ply_check.h"
#include "scene/scene_builder.h"
#include "scene/texture_decode.h"

namespace hrpp {
namespace {

// Triangulate: polygons to triangles (assimp's ear clipping; a convex polygon becomes a fan
// from its first vertex). SortByPType: points and lines apart, so they can be refused.
// FlipUVs: v from OBJ's and PLY's bottom-up to glTF's top-down texture rows.
constexpr unsigned kImportFlags = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_FlipUVs;

std::string one_line(std::string s) {
  for (char& c : s) {
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

const aiScene* import(Assimp::Importer& importer, const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw Error(file.string() + ": no such file");
  if (std::filesystem::is_directory(file, ec)) throw Error(file.string() + ": is a directory");
  const std::string ext = file.extension().string();
  if (ext == ".ply" || ext == ".PLY") check_ply_file(file);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, 0);
  const aiScene* scene = importer.ReadFile(file.string(), kImportFlags);
  if (scene == nullptr) {
    throw Error(one_line(file.string() + ": " + importer.GetErrorString()));
  }
  return scene;
}

glm::vec3 color(const aiMaterial& m, const char* key, unsigned type, unsigned index,
                glm::vec3 fallback) {
  aiColor3D c;
  if (m.Get(key, type, index, c) != AI_SUCCESS) return fallback;
  return glm::vec3(c.r, c.g, c.b);
}

float number(const aiMaterial& m, const char* key, unsigned type, unsigned index, float fallback) {
  float v = fallback;
  if (m.Get(key, type, index, v) != AI_SUCCESS) return fallback;
  return v;
}

MtlValues mtl_values(const aiMaterial& m) {
  MtlValues v;
  aiString name;
  if (m.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) v.name = name.C_Str();
  v.kd = color(m, AI_MATKEY_COLOR_DIFFUSE, v.kd);
  v.ks = color(m, AI_MATKEY_COLOR_SPECULAR, v.ks);
  v.ke = color(m, AI_MATKEY_COLOR_EMISSIVE, v.ke);
  v.ns = number(m, AI_MATKEY_SHININESS, v.ns);
  v.d = number(m, AI_MATKEY_OPACITY, v.d);
  v.ni = number(m, AI_MATKEY_REFRACTI, v.ni);
  int illum = -1;
  if (m.Get(AI_MATKEY_OBJ_ILLUM, illum) == AI_SUCCESS) v.illum = illum;
  return v;
}

class MeshFileReader {
 public:
  MeshFileReader(const aiScene& s, const std::filesystem::path& file)
      : s_(s), file_(file), name_(file.string()) {}

  Scene read() {
    Scene scene;
    scene.name = file_.filename().string();
    for (unsigned i = 0; i < s_.mNumMaterials; ++i) scene.materials.push_back(material(scene, i));
    if (scene.materials.empty()) scene.materials.push_back(Material{});
    walk(scene, *s_.mRootNode, aiMatrix4x4());
    for (const std::string& w : warnings_) scene.warnings.push_back(name_ + ": " + w);
    return scene;
  }

  // The mesh of a file's every triangle, ignoring materials (plymesh).
  IndexedMesh one_mesh() {
    IndexedMesh all;
    for (unsigned i = 0; i < s_.mNumMeshes; ++i) {
      const aiMesh& m = *s_.mMeshes[i];
      if (!(m.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      IndexedMesh part = mesh(m, "mesh " + std::to_string(i));
      if (!all.positions.empty() &&
          (all.normals.empty() != part.normals.empty() || all.uvs.empty() != part.uvs.empty())) {
        fail("meshes differ in their vertex attributes");
      }
      const auto base = static_cast<std::uint32_t>(all.positions.size());
      for (std::uint32_t& k : part.indices) k += base;
      append(all.positions, part.positions);
      append(all.normals, part.normals);
      append(all.uvs, part.uvs);
      append(all.indices, part.indices);
    }
    return all;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(one_line(name_ + ": " + what));
  }

  template <class T>
  static void append(std::vector<T>& to, const std::vector<T>& from) {
    to.insert(to.end(), from.begin(), from.end());
  }

  Material material(Scene& scene, unsigned i) {
    const aiMaterial& m = *s_.mMaterials[i];
    Material mat = material_from_mtl(mtl_values(m), warnings_);
    aiString tex;
    if (m.GetTexture(aiTextureType_DIFFUSE, 0, &tex) == AI_SUCCESS && tex.length > 0) {
      std::string rel = tex.C_Str();
      std::replace(rel.begin(), rel.end(), '\\', '/');
      const std::filesystem::path path = file_.parent_path() / rel;
      scene.textures.push_back(read_texture_file(path, name_ + ": material '" + mat.name + "'"));
      mat.base_color_texture = static_cast<int>(scene.textures.size() - 1);
    }
    return mat;
  }

  void walk(Scene& scene, const aiNode& node, const aiMatrix4x4& parent) {
    const aiMatrix4x4 world = parent * node.mTransformation;
    glm::dmat4 m(1.0);
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) m[c][r] = world[r][c];  // aiMatrix4x4 is row-major
    }
    for (unsigned k = 0; k < node.mNumMeshes; ++k) {
      const unsigned index = node.mMeshes[k];
      const aiMesh& am = *s_.mMeshes[index];
      const std::string where = name_ + ": mesh " + std::to_string(index);
      if (!(am.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
        refuse_non_triangles(am, where);
        continue;
      }
      MeshPlacement placement;
      placement.object_to_world = m;
      placement.material =
          std::min(am.mMaterialIndex, static_cast<unsigned>(scene.materials.size() - 1));
      append_mesh(scene, mesh(am, where), placement, where);
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c) walk(scene, *node.mChildren[c], world);
  }

  // A face of one or two vertices (OBJ's `f 1 2`, a PLY face list of two) is an error; a file
  // of points or lines only (a point cloud) is left to the "no triangles" check.
  void refuse_non_triangles(const aiMesh& m, const std::string& where) {
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      if (m.mFaces[f].mNumIndices < 3) {
        throw Error(where + ": face " + std::to_string(f) + " has fewer than three vertices (a " +
                    "point or line element: hrpp renders surfaces only)");
      }
    }
  }

  IndexedMesh mesh(const aiMesh& m, const std::string& where) const {
    IndexedMesh out;
    out.positions.resize(m.mNumVertices);
    for (unsigned v = 0; v < m.mNumVertices; ++v) {
      out.positions[v] = glm::vec3(m.mVertices[v].x, m.mVertices[v].y, m.mVertices[v].z);
    }
    if (m.HasNormals()) {
      out.normals.resize(m.mNumVertices);
      for (unsigned v = 0; v < m.mNumVertices; ++v) {
        out.normals[v] = glm::vec3(m.mNormals[v].x, m.mNormals[v].y, m.mNormals[v].z);
      }
    }
    if (m.HasTextureCoords(0)) {
      out.uvs.resize(m.mNumVertices);
      for (unsigned v = 0; v < m.mNumVertices; ++v) {
        out.uvs[v] = glm::vec2(m.mTextureCoords[0][v].x, m.mTextureCoords[0][v].y);
      }
    }
    out.indices.reserve(std::size_t{3} * m.mNumFaces);
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      const aiFace& face = m.mFaces[f];
      if (face.mNumIndices != 3) {
        throw Error(where + ": face " + std::to_string(f) + " has fewer than three vertices (a " +
                    "point or line element: hrpp renders surfaces only)");
      }
      out.indices.insert(out.indices.end(), face.mIndices, face.mIndices + 3);
    }
    return out;
  }

  const aiScene& s_;
  std::filesystem::path file_;
  std::string name_;
  std::vector<std::string> warnings_;
};

}  // namespace

Scene load_mesh_file(const std::filesystem::path& file) {
  Assimp::Importer importer;
  const aiScene* s = import(importer, file);
  return MeshFileReader(*s, file).read();
}

IndexedMesh read_ply_mesh(const std::filesystem::path& file, const std::string& where) {
  Assimp::Importer importer;
  try {
    const aiScene* s = import(importer, file);
    IndexedMesh mesh = MeshFileReader(*s, file).one_mesh();
    check_mesh(mesh, file.string());
    return mesh;
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
}

}  // namespace hrpp
