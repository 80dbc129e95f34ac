// load_obj_file(): tinyobjloader's LoadObjWithCallback hands over each `v`, `vn`, `vt`, `f`,
// `usemtl` and `mtllib` as it parses; faces become triangles at once. Errors are recorded by
// statement number and turned into a line number by a second look at the file, on that path
// alone.
#include "scene/obj_file.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "scene/mtl_material.h"
#include "scene/polygon.h"
#include "scene/scene_builder.h"
#include "scene/texture_decode.h"

namespace hrpp {
namespace {

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// What went wrong, in which statement of a kind ('v' or 'f', counted from 1).
struct ObjFault {
  char statement = 0;
  std::size_t ordinal = 0;
  std::string what;
};

struct ObjReader {
  std::filesystem::path file;
  Scene scene;
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs;
  std::uint32_t material = 0;  // Scene::materials index: 0 is the default, MTL's from 1
  std::size_t faces = 0;
  std::vector<std::string> warnings;
  ObjFault fault;
  std::vector<glm::vec3> p_, nr_;  // the face being read (kept: no allocation per face)
  std::vector<glm::vec2> uv_;
  std::vector<std::uint32_t> polygon_;

  bool failed() const { return fault.statement != 0; }

  void fail(char statement, std::size_t ordinal, const std::string& what) {
    if (!failed()) fault = ObjFault{statement, ordinal, what};
  }

  // A 1-based or negative (relative) OBJ index into a list of `count`; -1: out of range.
  static long resolve(int index, std::size_t count) {
    const long n = static_cast<long>(count);
    const long i = index > 0 ? index - 1L : n + index;
    return index != 0 && i >= 0 && i < n ? i : -1;
  }

  void face(const tinyobj::index_t* idx, int n) {
    ++faces;
    if (failed()) return;
    if (n < 3) return fail('f', faces, "a face of fewer than three vertices");
    p_.resize(static_cast<std::size_t>(n));
    nr_.resize(p_.size());
    uv_.resize(p_.size());
    std::vector<glm::vec3>& p = p_;
    std::vector<glm::vec3>& nr = nr_;
    std::vector<glm::vec2>& uv = uv_;
    for (std::size_t k = 0; k < p.size(); ++k) {
      const long v = resolve(idx[k].vertex_index, positions.size());
      if (v < 0) {
        return fail('f', faces,
                    "vertex index " + std::to_string(idx[k].vertex_index) + " is out of range (" +
                        std::to_string(positions.size()) + " vertices so far)");
      }
      p[k] = positions[static_cast<std::size_t>(v)];
      const long vn = idx[k].normal_index == 0 ? -2 : resolve(idx[k].normal_index, normals.size());
      const long vt = idx[k].texcoord_index == 0 ? -2 : resolve(idx[k].texcoord_index, uvs.size());
      if (vn == -1 || vt == -1)
        return fail('f', faces, "a normal or texture index is out of range");
      nr[k] = vn >= 0 ? normals[static_cast<std::size_t>(vn)] : glm::vec3(0.0f);
      uv[k] = vt >= 0 ? uvs[static_cast<std::size_t>(vt)] : glm::vec2(0.0f);
    }
    static const std::vector<std::uint32_t> kTriangle = {0, 1, 2};
    if (n != 3) polygon_ = triangulate_polygon(p);
    const std::vector<std::uint32_t>& tri = n == 3 ? kTriangle : polygon_;
    if (tri.size() / 3 > kMaxSceneTriangles - scene.triangles.size()) {
      return fail('f', faces, "more than " + std::to_string(kMaxSceneTriangles) + " triangles");
    }
    for (std::size_t t = 0; t < tri.size(); t += 3) {
      const std::uint32_t a = tri[t], b = tri[t + 1], c = tri[t + 2];
      scene.triangles.push_back(Triangle{p[a], p[b], p[c]});
      TriangleShading s;
      s.n0 = nr[a], s.n1 = nr[b], s.n2 = nr[c];
      s.uv0 = uv[a], s.uv1 = uv[b], s.uv2 = uv[c];
      s.material = material;
      scene.shading.push_back(s);
    }
  }

  void materials(const tinyobj::material_t* m, int n) {
    if (failed()) return;
    for (int i = 0; i < n; ++i) {
      MtlValues v;
      v.name = m[i].name;
      v.kd = glm::vec3(m[i].diffuse[0], m[i].diffuse[1], m[i].diffuse[2]);
      v.ks = glm::vec3(m[i].specular[0], m[i].specular[1], m[i].specular[2]);
      v.ke = glm::vec3(m[i].emission[0], m[i].emission[1], m[i].emission[2]);
      v.ns = m[i].shininess;
      v.d = m[i].dissolve;
      v.ni = m[i].ior;
      v.illum = m[i].illum;
      Material mat = material_from_mtl(v, warnings);
      if (!m[i].diffuse_texname.empty()) {
        std::string rel = m[i].diffuse_texname;
        std::replace(rel.begin(), rel.end(), '\\', '/');
        scene.textures.push_back(read_texture_file(file.parent_path() / rel,
                                                   file.string() + ": material '" + v.name + "'"));
        mat.base_color_texture = static_cast<int>(scene.textures.size() - 1);
      }
      scene.materials.push_back(std::move(mat));
    }
  }
};

ObjReader& reader(void* p) { return *static_cast<ObjReader*>(p); }

tinyobj::callback_t callbacks() {
  tinyobj::callback_t cb;
  cb.vertex_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z,
                    tinyobj::real_t) {
    ObjReader& r = reader(u);
    r.positions.emplace_back(x, y, z);
    if (!finite(r.positions.back())) {
      r.fail('v', r.positions.size(), "a non-finite coordinate (NaN or Inf)");
    }
  };
  cb.normal_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z) {
    reader(u).normals.emplace_back(x, y, z);
  };
  cb.texcoord_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t) {
    reader(u).uvs.emplace_back(x, 1.0f - y);  // OBJ's v runs up, glTF's texture rows down
  };
  cb.index_cb = [](void* u, tinyobj::index_t* idx, int n) { reader(u).face(idx, n); };
  cb.mtllib_cb = [](void* u, const tinyobj::material_t* m, int n) {
    ObjReader& r = reader(u);
    r.scene.materials.resize(1);  // tinyobjloader hands over every material read so far
    r.scene.textures.clear();
    try {
      r.materials(m, n);
    } catch (const Error& e) {
      r.fail('m', 0, e.what());
    }
  };
  cb.usemtl_cb = [](void* u, const char*, int id) {
    ObjReader& r = reader(u);
    r.material = id >= 0 && static_cast<std::size_t>(id) + 1 < r.scene.materials.size()
                     ? static_cast<std::uint32_t>(id) + 1
                     : 0u;
  };
  return cb;
}

// The line of the ordinal-th statement of a kind ('v': vertex, 'f': face), counted from 1.
int line_of(const std::filesystem::path& file, char statement, std::size_t ordinal) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  std::size_t seen = 0;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::size_t at = line.find_first_not_of(" \t");
    if (at == std::string::npos || line[at] != statement || at + 1 >= line.size() ||
        (line[at + 1] != ' ' && line[at + 1] != '\t'))
      continue;
    if (++seen == ordinal) return number;
  }
  return 0;
}

// tinyobjloader reads a number it cannot parse (nan, inf, a word) as 0 without a word: refuse
// such a `v`, `vn` or `vt` line first. A letter other than an exponent's e in one of their
// numbers is the sign; the scan looks at characters only, a megabyte at a time, so it costs a
// fraction of the parse.
class VertexNumberScan {
 public:
  explicit VertexNumberScan(const std::filesystem::path& file) : file_(file) {}

  void run() {
    std::ifstream in(file_, std::ios::binary);
    std::vector<char> buf(std::size_t{1} << 20);
    while (in) {
      in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
      const auto n = static_cast<std::size_t>(in.gcount());
      for (std::size_t i = 0; i < n; ++i) step(buf[i]);
    }
  }

 private:
  enum State { kLineStart, kV, kVn, kNumbers, kSkip };

  void step(char c) {
    if (c == '\n') {
      ++line_;
      state_ = kLineStart;
      return;
    }
    switch (state_) {
      case kLineStart:
        if (c == 'v')
          state_ = kV;
        else if (c != ' ' && c != '\t')
          state_ = kSkip;
        return;
      case kV:  // "v", "vn" or "vt" must be followed by a blank
        if (c == 'n' || c == 't')
          state_ = kVn;
        else
          state_ = c == ' ' || c == '\t' ? kNumbers : kSkip;
        return;
      case kVn:
        state_ = c == ' ' || c == '\t' ? kNumbers : kSkip;
        return;
      case kNumbers:
        if (c == '#')
          state_ = kSkip;
        else if (((c | 0x20) >= 'a' && (c | 0x20) <= 'z') && (c | 0x20) != 'e')
          refuse();
        return;
      case kSkip:
        return;
    }
  }

  [[noreturn]] void refuse() const {
    throw Error(file_.string() + ":" + std::to_string(line_) +
                ": a coordinate that is not a finite number (NaN, Inf or a word)");
  }

  std::filesystem::path file_;
  int line_ = 1;
  State state_ = kLineStart;
};

}  // namespace

Scene load_obj_file(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw Error(file.string() + ": no such file");
  if (std::filesystem::is_directory(file, ec)) throw Error(file.string() + ": is a directory");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": cannot open for reading");
  ObjReader r;
  r.file = file;
  r.scene.name = file.filename().string();
  VertexNumberScan(file).run();
  const std::string dir = file.parent_path().empty() ? "." : file.parent_path().string();
  tinyobj::MaterialFileReader mtl(dir + "/");
  std::string warn, err;
  Material fallback;
  fallback.name = "default";
  r.scene.materials.push_back(fallback);
  const tinyobj::callback_t cb = callbacks();
  const bool ok = tinyobj::LoadObjWithCallback(in, cb, &r, &mtl, &warn, &err);
  if (r.failed()) {
    const int line =
        r.fault.statement == 'm' ? 0 : line_of(file, r.fault.statement, r.fault.ordinal);
    throw Error(r.fault.statement == 'm'
                    ? r.fault.what
                    : file.string() + ":" + std::to_string(line) + ": " + r.fault.what);
  }
  if (!ok) throw Error(file.string() + ": " + err.substr(0, err.find('\n')));
  std::istringstream lines(warn);
  for (std::string w; std::getline(lines, w);) {
    if (!w.empty()) r.warnings.push_back(w);
  }
  for (const std::string& w : r.warnings) {
    r.scene.warnings.push_back(file.string() + ": " + w);
    std::fprintf(stderr, "hrpp: warning: %s\n", r.scene.warnings.back().c_str());
  }
  return std::move(r.scene);
}

}  // namespace hrpp
