// check_ply_file(): Greg Turk's PLY format (a text header, then every element's instances in
// order, as ASCII lines or binary records).
#include "scene/ply_check.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "common/error.h"

namespace hrpp {
namespace {

struct PlyProperty {
  int size = 0;            // bytes of a scalar, or of each list item
  int count_size = 0;      // a list: bytes of its count; 0: a scalar
  bool is_signed = false;  // an integer item type with a sign (char, short, int)
  std::string name;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

constexpr std::uint64_t kMaxListItems = std::uint64_t{1} << 24;

enum class PlyFormat { kAscii, kLittle, kBig };

int type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32")
    return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

class PlyChecker {
 public:
  PlyChecker(std::string name, std::string bytes) : name_(std::move(name)), b_(std::move(bytes)) {}

  void check() {
    read_header();
    for (const PlyElement& e : elements_) {
      if (e.name == "vertex") {
        vertices_ = static_cast<long long>(std::min<std::uint64_t>(e.count, 1ULL << 62));
        break;
      }
      if (e.name == "face") break;  // faces before vertices: left to assimp
    }
    for (const PlyElement& e : elements_) {
      for (std::uint64_t i = 0; i < e.count; ++i) {
        for (const PlyProperty& p : e.properties) property(e, p, i);
      }
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(name_ + ": " + what); }

  void read_header() {
    if (b_.compare(0, 3, "ply") != 0) fail("not a PLY file (it does not start with 'ply')");
    const std::size_t end = b_.find("end_header");
    if (end == std::string::npos) fail("the PLY header has no end_header");
    const std::size_t nl = b_.find('\n', end);
    if (nl == std::string::npos) fail("the PLY header's end_header line has no line end");
    pos_ = nl + 1;
    std::istringstream lines(b_.substr(0, end));
    std::string line;
    std::getline(lines, line);
    int number = 1;
    while (std::getline(lines, line)) header_line(line, ++number);
    if (!has_format_) fail("the PLY header has no format line");
  }

  void header_line(const std::string& line, int number) {
    std::istringstream w(line);
    std::string key;
    if (!(w >> key) || key == "comment" || key == "obj_info") return;
    const std::string at = "header line " + std::to_string(number) + ": ";
    if (key == "format") {
      std::string f;
      w >> f;
      if (f == "ascii")
        format_ = PlyFormat::kAscii;
      else if (f == "binary_little_endian")
        format_ = PlyFormat::kLittle;
      else if (f == "binary_big_endian")
        format_ = PlyFormat::kBig;
      else
        fail(at + "unknown format '" + f + "'");
      has_format_ = true;
    } else if (key == "element") {
      PlyElement e;
      long long count = -1;
      if (!(w >> e.name >> count) || count < 0) fail(at + "expected 'element NAME COUNT'");
      e.count = static_cast<std::uint64_t>(count);
      elements_.push_back(e);
    } else if (key == "property") {
      if (elements_.empty()) fail(at + "a property before any element");
      elements_.back().properties.push_back(property_decl(w, at));
    } else {
      fail(at + "unknown header keyword '" + key + "'");
    }
  }

  PlyProperty property_decl(std::istringstream& w, const std::string& at) const {
    std::string type;
    w >> type;
    PlyProperty p;
    if (type == "list") {
      std::string count_type, item_type;
      w >> count_type >> item_type >> p.name;
      p.count_size = type_size(count_type);
      p.size = type_size(item_type);
      p.is_signed = item_type == "char" || item_type == "short" || item_type == "int" ||
                    item_type == "int8" || item_type == "int16" || item_type == "int32";
      if (p.count_size == 0 || p.size == 0 || p.count_size == 8)
        fail(at + "bad list property types");
    } else {
      w >> p.name;
      p.size = type_size(type);
      if (p.size == 0) fail(at + "unknown property type '" + type + "'");
    }
    return p;
  }

  [[noreturn]] void truncated(const PlyElement& e, std::uint64_t i) const {
    fail("truncated: the header declares " + std::to_string(e.count) + " " + e.name +
         " elements, the file ends in number " + std::to_string(i));
  }

  void property(const PlyElement& e, const PlyProperty& p, std::uint64_t i) {
    std::uint64_t items = 1;
    if (p.count_size > 0) {
      items = format_ == PlyFormat::kAscii ? ascii_count(e, i) : binary_count(e, p, i);
      if (e.name == "face" && items < 3) {
        fail("face " + std::to_string(i) + " has fewer than three vertices (" +
             std::to_string(items) + ")");
      }
    }
    // A face's vertex indices are checked here: assimp leaks its half-built mesh when it
    // meets one out of range.
    const bool indices = e.name == "face" && p.count_size > 0 &&
                         (p.name == "vertex_indices" || p.name == "vertex_index");
    if (format_ == PlyFormat::kAscii) {
      for (std::uint64_t k = 0; k < items; ++k) {
        const std::string_view t = ascii_token();
        if (t.empty()) truncated(e, i);
        if (indices) check_index(std::strtoll(std::string(t).c_str(), nullptr, 10), i);
      }
    } else {
      const std::uint64_t bytes = items * static_cast<std::uint64_t>(p.size);
      if (bytes > b_.size() - pos_) truncated(e, i);
      if (indices && p.size <= 4) {
        for (std::uint64_t k = 0; k < items; ++k) check_index(binary_int(p, pos_ + k * p.size), i);
      }
      pos_ += bytes;
    }
  }

  long long binary_int(const PlyProperty& p, std::size_t at) const {
    std::uint64_t v = 0;
    for (int k = 0; k < p.size; ++k) {
      const int byte = format_ == PlyFormat::kLittle ? k : p.size - 1 - k;
      v |= static_cast<std::uint64_t>(static_cast<unsigned char>(b_[at + byte])) << (8 * k);
    }
    const int bits = 8 * p.size;
    if (p.is_signed && bits < 64 && (v >> (bits - 1)) != 0)
      return static_cast<long long>(v) - (1LL << bits);
    return static_cast<long long>(v);
  }

  void check_index(long long v, std::uint64_t face) const {
    if (vertices_ >= 0 && (v < 0 || v >= vertices_)) {
      fail("face " + std::to_string(face) + ": vertex index " + std::to_string(v) +
           " is out of range (" + std::to_string(vertices_) + " vertices)");
    }
  }

  std::uint64_t binary_count(const PlyElement& e, const PlyProperty& p, std::uint64_t i) {
    if (static_cast<std::size_t>(p.count_size) > b_.size() - pos_) truncated(e, i);
    std::uint64_t v = 0;
    for (int k = 0; k < p.count_size; ++k) {
      const int byte = format_ == PlyFormat::kLittle ? k : p.count_size - 1 - k;
      v |= static_cast<std::uint64_t>(static_cast<unsigned char>(b_[pos_ + byte])) << (8 * k);
    }
    pos_ += static_cast<std::size_t>(p.count_size);
    if (v > kMaxListItems) {  // also a negative count read as unsigned
      fail(e.name + " " + std::to_string(i) + ": list count " + std::to_string(v) +
           " is not valid");
    }
    return v;
  }

  std::uint64_t ascii_count(const PlyElement& e, std::uint64_t i) {
    const std::string_view t = ascii_token();
    if (t.empty()) truncated(e, i);
    char* end = nullptr;
    const std::string s(t);
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (end != s.c_str() + s.size() || v < 0) {
      fail(e.name + " " + std::to_string(i) + ": list count '" + s + "' is not a count");
    }
    return static_cast<std::uint64_t>(v);
  }

  std::string_view ascii_token() {
    while (pos_ < b_.size() && std::isspace(static_cast<unsigned char>(b_[pos_]))) ++pos_;
    const std::size_t start = pos_;
    while (pos_ < b_.size() && !std::isspace(static_cast<unsigned char>(b_[pos_]))) ++pos_;
    return std::string_view(b_).substr(start, pos_ - start);
  }

  std::string name_;
  std::string b_;
  std::size_t pos_ = 0;
  PlyFormat format_ = PlyFormat::kAscii;
  bool has_format_ = false;
  std::vector<PlyElement> elements_;
  long long vertices_ = -1;  // the vertex element's count, when it comes before the faces
};

}  // namespace

void check_ply_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) throw Error(file.string() + ": cannot open for reading");
  std::string bytes(static_cast<std::size_t>(std::max<std::streamoff>(in.tellg(), 0)), '\0');
  in.seekg(0);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  PlyChecker(file.string(), std::move(bytes)).check();
}

}  // namespace hrpp
