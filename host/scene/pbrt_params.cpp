// PbrtParams: pbrt-v4's parameter syntax (src/pbrt/parser.cpp, parseParameters) and lookups.
#include "scene/pbrt_params.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "common/error.h"

namespace hrpp {
namespace {

const char* const kTypes[] = {"integer",  "float",  "point2", "vector2", "point3", "vector3",
                              "normal3",  "normal", "point",  "vector",  "rgb",    "blackbody",
                              "spectrum", "bool",   "string", "texture", "color"};

// "point" etc. are pbrt-v3's names for the 3D types; "color" its name for rgb.
std::string canonical_type(const std::string& t) {
  if (t == "point") return "point3";
  if (t == "vector") return "vector3";
  if (t == "normal") return "normal3";
  if (t == "color") return "rgb";
  return t;
}

bool is_number(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && errno != ERANGE;
}

// The normalised colour of a black body at `kelvin`: Planck's law weighted by Wyman, Sloan and
// Shirley's (2013) fit of the CIE 1931 observer, to linear sRGB, brightest channel 1.
glm::vec3 blackbody_rgb(double kelvin) {
  auto g = [](double x, double mu, double s1, double s2) {
    const double t = (x - mu) / (x < mu ? s1 : s2);
    return std::exp(-0.5 * t * t);
  };
  glm::dvec3 xyz(0.0);
  for (double nm = 360.0; nm <= 830.0; nm += 5.0) {
    const double l = nm * 1e-9;
    const double planck = 1.0 / (std::pow(l, 5) * (std::exp(1.4387769e-2 / (l * kelvin)) - 1.0));
    const double x = 1.056 * g(nm, 599.8, 37.9, 31.0) + 0.362 * g(nm, 442.0, 16.0, 26.7) -
                     0.065 * g(nm, 501.1, 20.4, 26.2);
    const double y = 0.821 * g(nm, 568.8, 46.9, 40.5) + 0.286 * g(nm, 530.9, 16.3, 31.1);
    const double z = 1.217 * g(nm, 437.0, 11.8, 36.0) + 0.681 * g(nm, 459.0, 26.0, 13.8);
    xyz += planck * glm::dvec3(x, y, z);
  }
  const glm::dvec3 rgb(3.2404542 * xyz.x - 1.5371385 * xyz.y - 0.4985314 * xyz.z,
                       -0.9692660 * xyz.x + 1.8760108 * xyz.y + 0.0415560 * xyz.z,
                       0.0556434 * xyz.x - 0.2040259 * xyz.y + 1.0572252 * xyz.z);
  const glm::dvec3 pos = glm::max(rgb, glm::dvec3(0.0));
  const double peak = std::max(pos.x, std::max(pos.y, pos.z));
  return peak > 0.0 ? glm::vec3(pos / peak) : glm::vec3(1.0f);
}

struct Reader {
  PbrtTokenizer& in;

  [[noreturn]] void fail(int line, const std::string& what) const {
    throw Error(in.file() + ":" + std::to_string(line) + ": " + what);
  }

  void value(PbrtParam& p, const PbrtToken& t) const {
    if (t.kind == PbrtToken::kString) {
      if (p.type == "bool") {
        if (t.text != "true" && t.text != "false")
          fail(t.line, "bool \"" + p.name + "\": \"" + t.text + "\" is neither true nor false");
        p.bools.push_back(t.text == "true");
      } else {
        p.strings.push_back(t.text);
      }
      return;
    }
    if (t.text == "true" || t.text == "false") {
      p.bools.push_back(t.text == "true");
      return;
    }
    double d = 0.0;
    if (!is_number(t.text, d))
      fail(t.line, "parameter \"" + p.name + "\": \"" + t.text + "\" is not a number");
    p.numbers.push_back(d);
  }

  PbrtParam param(const PbrtToken& decl) const {
    std::string type, name;
    std::size_t i = decl.text.find_first_not_of(" \t");
    const std::size_t sp = decl.text.find_first_of(" \t", i == std::string::npos ? 0 : i);
    if (i == std::string::npos || sp == std::string::npos)
      fail(decl.line, "parameter \"" + decl.text + "\": expected \"type name\"");
    type = canonical_type(decl.text.substr(i, sp - i));
    const std::size_t ns = decl.text.find_first_not_of(" \t", sp);
    if (ns == std::string::npos)
      fail(decl.line, "parameter \"" + decl.text + "\": expected \"type name\"");
    name = decl.text.substr(ns);
    while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.pop_back();
    if (std::find(std::begin(kTypes), std::end(kTypes), type) == std::end(kTypes)) {
      fail(decl.line, "parameter \"" + decl.text + "\": unknown type \"" + type + "\"");
    }
    PbrtParam p{type, name, {}, {}, {}, decl.line, false};
    const std::optional<PbrtToken> first = in.next();
    if (!first) fail(decl.line, "parameter \"" + name + "\" has no value");
    if (first->kind == PbrtToken::kOpenBracket) {
      while (true) {
        const std::optional<PbrtToken> t = in.next();
        if (!t) fail(decl.line, "parameter \"" + name + "\": missing ]");
        if (t->kind == PbrtToken::kCloseBracket) break;
        if (t->kind == PbrtToken::kOpenBracket)
          fail(t->line, "parameter \"" + name + "\": nested [");
        value(p, *t);
      }
    } else if (first->kind == PbrtToken::kCloseBracket) {
      fail(first->line, "parameter \"" + name + "\": unexpected ]");
    } else {
      value(p, *first);
    }
    return p;
  }
};

}  // namespace

PbrtParams PbrtParams::parse(PbrtTokenizer& in, int directive_line) {
  std::vector<PbrtParam> params;
  Reader r{in};
  while (true) {
    const std::optional<PbrtToken>& t = in.peek();
    if (!t || t->kind != PbrtToken::kString) break;
    const PbrtToken decl = *in.next();
    PbrtParam p = r.param(decl);
    for (const PbrtParam& q : params) {
      if (q.name == p.name) r.fail(decl.line, "parameter \"" + p.name + "\" given twice");
    }
    params.push_back(std::move(p));
  }
  return PbrtParams(std::move(params), in.file(), directive_line);
}

const PbrtParam* PbrtParams::find(const std::string& name,
                                  std::initializer_list<const char*> types) const {
  for (const PbrtParam& p : params_) {
    if (p.name != name) continue;
    for (const char* t : types) {
      if (p.type == t) {
        p.used = true;
        return &p;
      }
    }
  }
  return nullptr;
}

void PbrtParams::fail(const PbrtParam& p, const std::string& what) const {
  throw Error(file_ + ":" + std::to_string(p.line) + ": \"" + p.type + " " + p.name +
              "\": " + what);
}

float PbrtParams::get_float(const std::string& name, float fallback) const {
  const PbrtParam* p = find(name, {"float"});
  if (!p) return fallback;
  if (p->numbers.size() != 1) fail(*p, "expected one number");
  if (!std::isfinite(p->numbers[0])) fail(*p, "not a finite number");
  return static_cast<float>(p->numbers[0]);
}

int PbrtParams::get_int(const std::string& name, int fallback) const {
  const PbrtParam* p = find(name, {"integer"});
  if (!p) return fallback;
  if (p->numbers.size() != 1) fail(*p, "expected one integer");
  const double d = p->numbers[0];
  if (d != std::floor(d) || std::fabs(d) > 2147483647.0) fail(*p, "not an integer");
  return static_cast<int>(d);
}

bool PbrtParams::get_bool(const std::string& name, bool fallback) const {
  const PbrtParam* p = find(name, {"bool"});
  if (!p) return fallback;
  if (p->bools.size() != 1) fail(*p, "expected one of true or false");
  return p->bools[0];
}

std::string PbrtParams::get_string(const std::string& name, const std::string& fallback) const {
  const PbrtParam* p = find(name, {"string"});
  if (!p) return fallback;
  if (p->strings.size() != 1) fail(*p, "expected one string");
  return p->strings[0];
}

std::vector<double> PbrtParams::get_floats(const std::string& name) const {
  const PbrtParam* p = find(name, {"float"});
  if (!p) return {};
  if (!p->strings.empty() || !p->bools.empty()) fail(*p, "expected numbers");
  return p->numbers;
}

std::vector<int> PbrtParams::get_ints(const std::string& name) const {
  const PbrtParam* p = find(name, {"integer"});
  if (!p) return {};
  std::vector<int> v;
  v.reserve(p->numbers.size());
  for (double d : p->numbers) {
    if (d != std::floor(d) || std::fabs(d) > 2147483647.0) fail(*p, "not an integer");
    v.push_back(static_cast<int>(d));
  }
  return v;
}

std::vector<glm::vec3> PbrtParams::get_point3s(const std::string& name) const {
  const PbrtParam* p = find(name, {"point3", "vector3", "normal3"});
  if (!p) return {};
  if (p->numbers.size() % 3 != 0 || !p->strings.empty()) fail(*p, "expected triples of numbers");
  std::vector<glm::vec3> v(p->numbers.size() / 3);
  for (std::size_t i = 0; i < v.size(); ++i) {
    v[i] = glm::vec3(glm::dvec3(p->numbers[3 * i], p->numbers[3 * i + 1], p->numbers[3 * i + 2]));
  }
  return v;
}

std::vector<glm::vec2> PbrtParams::get_point2s(const std::string& name) const {
  const PbrtParam* p = find(name, {"point2", "vector2", "float"});
  if (!p) return {};
  if (p->numbers.size() % 2 != 0 || !p->strings.empty()) fail(*p, "expected pairs of numbers");
  std::vector<glm::vec2> v(p->numbers.size() / 2);
  for (std::size_t i = 0; i < v.size(); ++i) {
    v[i] = glm::vec2(glm::dvec2(p->numbers[2 * i], p->numbers[2 * i + 1]));
  }
  return v;
}

std::optional<glm::vec3> PbrtParams::get_rgb(const std::string& name) const {
  const PbrtParam* p = find(name, {"rgb", "blackbody", "spectrum", "float"});
  if (!p) return std::nullopt;
  if (p->type == "rgb") {
    if (p->numbers.size() != 3) fail(*p, "expected three numbers");
    const glm::vec3 c(glm::dvec3(p->numbers[0], p->numbers[1], p->numbers[2]));
    if (!std::isfinite(c.x + c.y + c.z)) fail(*p, "not finite");
    return c;
  }
  if (p->type == "blackbody") {
    if (p->numbers.size() != 1 || !(p->numbers[0] > 0.0)) fail(*p, "expected one temperature");
    return blackbody_rgb(p->numbers[0]);
  }
  if (p->type == "float") {  // a scalar where a spectrum may go (pbrt's constant spectrum)
    if (p->numbers.size() != 1) fail(*p, "expected one number");
    return glm::vec3(static_cast<float>(p->numbers[0]));
  }
  p->used = false;  // a spectrum: left to get_spectrum_name
  return std::nullopt;
}

std::optional<std::string> PbrtParams::get_spectrum_name(const std::string& name) const {
  const PbrtParam* p = find(name, {"spectrum"});
  if (!p) return std::nullopt;
  if (p->strings.size() == 1) return p->strings[0];
  return std::string();  // sampled (wavelength, value) pairs: not read
}

std::optional<std::string> PbrtParams::get_texture(const std::string& name) const {
  const PbrtParam* p = find(name, {"texture"});
  if (!p) return std::nullopt;
  if (p->strings.size() != 1) fail(*p, "expected one texture name");
  return p->strings[0];
}

bool PbrtParams::has(const std::string& name) const {
  for (const PbrtParam& p : params_) {
    if (p.name == name) return true;
  }
  return false;
}

std::vector<std::string> PbrtParams::unused() const {
  std::vector<std::string> out;
  for (const PbrtParam& p : params_) {
    if (!p.used) out.push_back(p.type + " " + p.name);
  }
  return out;
}

}  // namespace hrpp
