// A pbrt-v4 parameter list (`"float fov" [ 39 ]`, `"rgb L" [1 1 1]`, `"string filename" "a.ply"`)
// and typed lookups that remember which parameters were used, so that the rest can be
// reported: an unused shape parameter is an error, as in pbrt-v4; an unused material or light
// parameter a warning.
#pragma once

#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scene/pbrt_tokenizer.h"

namespace hrpp {

struct PbrtParam {
  std::string type;  // integer float point2 vector2 point3 vector3 normal3 rgb blackbody
                     // spectrum bool string texture (point, vector, normal: their 3D forms)
  std::string name;
  std::vector<double> numbers;
  std::vector<std::string> strings;
  std::vector<bool> bools;
  int line = 0;
  mutable bool used = false;
};

class PbrtParams {
 public:
  PbrtParams() = default;
  PbrtParams(std::vector<PbrtParam> params, std::string file, int line)
      : params_(std::move(params)), file_(std::move(file)), line_(line) {}

  // Reads `"type name" value...` pairs until the next token is not a string.
  static PbrtParams parse(PbrtTokenizer& in, int directive_line);

  float get_float(const std::string& name, float fallback) const;
  int get_int(const std::string& name, int fallback) const;
  bool get_bool(const std::string& name, bool fallback) const;
  std::string get_string(const std::string& name, const std::string& fallback) const;
  std::vector<double> get_floats(const std::string& name) const;      // float, any count
  std::vector<int> get_ints(const std::string& name) const;           // integer, any count
  std::vector<glm::vec3> get_point3s(const std::string& name) const;  // point3/vector3/normal3
  std::vector<glm::vec2> get_point2s(const std::string& name) const;  // point2/vector2, or float uv
  // An rgb, a blackbody (approximated as its normalised sRGB colour), or a spectrum as a named
  // constant; nothing when the parameter is absent or is a texture.
  std::optional<glm::vec3> get_rgb(const std::string& name) const;
  // A spectrum parameter given as a name (`"spectrum eta" "metal-Au-eta"`).
  std::optional<std::string> get_spectrum_name(const std::string& name) const;
  std::optional<std::string> get_texture(const std::string& name) const;
  bool has(const std::string& name) const;

  // "<type> <name>" of every parameter no lookup asked for.
  std::vector<std::string> unused() const;
  // "<file>:<line>: " of the directive.
  std::string where() const { return file_ + ":" + std::to_string(line_) + ": "; }

 private:
  const PbrtParam* find(const std::string& name, std::initializer_list<const char*> types) const;
  [[noreturn]] void fail(const PbrtParam& p, const std::string& what) const;

  std::vector<PbrtParam> params_;
  std::string file_;
  int line_ = 0;
};

}  // namespace hrpp
