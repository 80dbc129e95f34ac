#include "gltf_writer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace hrpp::test {

using nlohmann::json;

GltfWriter::GltfWriter() { doc["asset"] = {{"version", "2.0"}, {"generator", "hrpp gltf_writer"}}; }

int GltfWriter::append(const char* array, const json& value) {
  if (!doc.contains(array)) doc[array] = json::array();
  doc[array].push_back(value);
  return static_cast<int>(doc[array].size() - 1);
}

int GltfWriter::add_buffer_view(const void* data, std::size_t bytes, std::size_t stride) {
  while (bin.size() % 4 != 0) bin.push_back(0);
  const std::size_t offset = bin.size();
  const auto* p = static_cast<const std::uint8_t*>(data);
  bin.insert(bin.end(), p, p + bytes);
  json bv = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
  if (stride != 0) bv["byteStride"] = stride;
  return append("bufferViews", bv);
}

int GltfWriter::add_accessor(int buffer_view, int component_type, std::size_t count,
                             const std::string& type, std::size_t byte_offset, bool normalized) {
  json a = {{"bufferView", buffer_view},
            {"componentType", component_type},
            {"count", count},
            {"type", type}};
  if (byte_offset != 0) a["byteOffset"] = byte_offset;
  if (normalized) a["normalized"] = true;
  return append("accessors", a);
}

int GltfWriter::add_vec3(const std::vector<glm::vec3>& v) {
  const int bv = add_buffer_view(v.data(), v.size() * sizeof(glm::vec3));
  const int acc = add_accessor(bv, kFloat, v.size(), "VEC3");
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  bool finite = !v.empty();
  for (const glm::vec3& p : v) {
    finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (finite) {
    doc["accessors"][acc]["min"] = {lo.x, lo.y, lo.z};
    doc["accessors"][acc]["max"] = {hi.x, hi.y, hi.z};
  }
  return acc;
}

int GltfWriter::add_vec2(const std::vector<glm::vec2>& v) {
  const int bv = add_buffer_view(v.data(), v.size() * sizeof(glm::vec2));
  return add_accessor(bv, kFloat, v.size(), "VEC2");
}

int GltfWriter::add_indices(const std::vector<std::uint32_t>& idx, int component_type) {
  std::vector<std::uint8_t> bytes;
  for (std::uint32_t i : idx) {
    if (component_type == kUnsignedByte) {
      bytes.push_back(static_cast<std::uint8_t>(i));
    } else if (component_type == kUnsignedShort) {
      const auto s = static_cast<std::uint16_t>(i);
      bytes.insert(bytes.end(), {static_cast<std::uint8_t>(s & 0xff),
                                 static_cast<std::uint8_t>(s >> 8)});
    } else {
      for (int b = 0; b < 4; ++b) bytes.push_back(static_cast<std::uint8_t>(i >> (8 * b)));
    }
  }
  const int bv = add_buffer_view(bytes.data(), bytes.size());
  return add_accessor(bv, component_type, idx.size(), "SCALAR");
}

json GltfWriter::primitive(int position, int indices, int material, int normal, int texcoord0,
                           int mode) {
  json p;
  p["attributes"] = json::object();
  if (position >= 0) p["attributes"]["POSITION"] = position;
  if (normal >= 0) p["attributes"]["NORMAL"] = normal;
  if (texcoord0 >= 0) p["attributes"]["TEXCOORD_0"] = texcoord0;
  if (indices >= 0) p["indices"] = indices;
  if (material >= 0) p["material"] = material;
  if (mode != kModeTriangles) p["mode"] = mode;
  return p;
}

int GltfWriter::add_mesh(const std::vector<json>& primitives) {
  return append("meshes", json{{"primitives", primitives}});
}

int GltfWriter::add_triangles(const std::vector<glm::vec3>& positions,
                              const std::vector<std::uint32_t>& indices, int material,
                              int index_type) {
  const int pos = add_vec3(positions);
  const int idx = indices.empty() ? -1 : add_indices(indices, index_type);
  return add_mesh({primitive(pos, idx, material)});
}

int GltfWriter::add_node(int mesh, const std::vector<int>& children) {
  json n = json::object();
  if (mesh >= 0) n["mesh"] = mesh;
  if (!children.empty()) n["children"] = children;
  return append("nodes", n);
}

int GltfWriter::add_scene(const std::vector<int>& roots) {
  const int s = append("scenes", json{{"nodes", roots}});
  if (!doc.contains("scene")) doc["scene"] = s;
  return s;
}

int GltfWriter::add_material(const json& material) { return append("materials", material); }

int GltfWriter::add_camera_perspective(float yfov, float aspect) {
  json p = {{"yfov", yfov}, {"znear", 0.01}};
  if (aspect > 0.0f) p["aspectRatio"] = aspect;
  return append("cameras", json{{"type", "perspective"}, {"perspective", p}});
}

int GltfWriter::add_light(const json& light) {
  if (!doc.contains("extensionsUsed")) doc["extensionsUsed"] = json::array();
  bool declared = false;
  for (const auto& e : doc["extensionsUsed"]) declared = declared || e == "KHR_lights_punctual";
  if (!declared) doc["extensionsUsed"].push_back("KHR_lights_punctual");
  json& lights = doc["extensions"]["KHR_lights_punctual"]["lights"];
  if (!lights.is_array()) lights = json::array();
  lights.push_back(light);
  return static_cast<int>(lights.size() - 1);
}

void GltfWriter::attach_light(int node, int light) {
  doc["nodes"][node]["extensions"]["KHR_lights_punctual"]["light"] = light;
}

int GltfWriter::add_png_texture(const std::vector<std::uint8_t>& png) {
  const int bv = add_buffer_view(png.data(), png.size());
  const int image = append("images", json{{"bufferView", bv}, {"mimeType", "image/png"}});
  return append("textures", json{{"source", image}});
}

namespace {

std::string base64(const std::vector<std::uint8_t>& data) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < data.size(); i += 3) {
    const std::uint32_t v = (data[i] << 16) | (data[i + 1] << 8) | data[i + 2];
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += k[(v >> 6) & 63];
    out += k[v & 63];
  }
  if (i + 1 == data.size()) {
    const std::uint32_t v = data[i] << 16;
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == data.size()) {
    const std::uint32_t v = (data[i] << 16) | (data[i + 1] << 8);
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += k[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

void put_u32le(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<std::uint8_t>(v >> (8 * b)));
}

void put_u32be(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int b = 3; b >= 0; --b) out.push_back(static_cast<std::uint8_t>(v >> (8 * b)));
}

std::uint32_t crc32(const std::uint8_t* p, std::size_t n) {
  std::uint32_t c = 0xffffffffu;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

void png_chunk(std::vector<std::uint8_t>& out, const char* type,
               const std::vector<std::uint8_t>& data) {
  put_u32be(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  put_u32be(out, crc32(out.data() + start, out.size() - start));
}

}  // namespace

std::string GltfWriter::json_text(const std::string& buffer_uri) const {
  json d = doc;
  if (!bin.empty() && !d.contains("buffers")) {
    json b = {{"byteLength", bin.size()}};
    if (!buffer_uri.empty()) b["uri"] = buffer_uri;
    d["buffers"] = json::array({b});
  }
  return d.dump(1);
}

std::vector<std::uint8_t> GltfWriter::glb_bytes() const {
  std::string text = json_text("");
  while (text.size() % 4 != 0) text.push_back(' ');
  std::vector<std::uint8_t> chunk = bin;
  while (chunk.size() % 4 != 0) chunk.push_back(0);
  std::vector<std::uint8_t> out;
  const std::size_t total = 12 + 8 + text.size() + (chunk.empty() ? 0 : 8 + chunk.size());
  out.insert(out.end(), {'g', 'l', 'T', 'F'});
  put_u32le(out, 2);
  put_u32le(out, static_cast<std::uint32_t>(total));
  put_u32le(out, static_cast<std::uint32_t>(text.size()));
  put_u32le(out, 0x4E4F534Au);  // JSON
  out.insert(out.end(), text.begin(), text.end());
  if (!chunk.empty()) {
    put_u32le(out, static_cast<std::uint32_t>(chunk.size()));
    put_u32le(out, 0x004E4942u);  // BIN
    out.insert(out.end(), chunk.begin(), chunk.end());
  }
  return out;
}

void GltfWriter::write(const std::filesystem::path& file, Container container) const {
  if (container == Container::kAuto) {
    container = file.extension() == ".glb" ? Container::kGlb : Container::kGltfBin;
  }
  switch (container) {
    case Container::kGlb: write_file(file, glb_bytes()); break;
    case Container::kGltfDataUri:
      write_file(file, json_text("data:application/octet-stream;base64," + base64(bin)));
      break;
    default: {
      std::filesystem::path bin_file = file;
      bin_file.replace_extension(".bin");
      if (!bin.empty()) write_file(bin_file, bin);
      write_file(file, json_text(bin_file.filename().string()));
    }
  }
}

std::vector<std::uint8_t> make_png(int width, int height, const std::vector<std::uint8_t>& rgba) {
  // Raw scanlines: filter byte 0 + RGBA row.
  std::vector<std::uint8_t> raw;
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);
    const auto row = rgba.begin() + static_cast<std::ptrdiff_t>(y) * width * 4;
    raw.insert(raw.end(), row, row + width * 4);
  }
  // zlib stream of stored deflate blocks (≤ 65535 bytes each) + Adler-32.
  std::vector<std::uint8_t> z = {0x78, 0x01};
  std::size_t pos = 0;
  do {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - pos);
    const bool last = pos + n == raw.size();
    z.push_back(last ? 1 : 0);
    const auto len = static_cast<std::uint16_t>(n);
    const auto nlen = static_cast<std::uint16_t>(~len);
    z.insert(z.end(), {static_cast<std::uint8_t>(len & 0xff), static_cast<std::uint8_t>(len >> 8),
                       static_cast<std::uint8_t>(nlen & 0xff),
                       static_cast<std::uint8_t>(nlen >> 8)});
    z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(pos),
             raw.begin() + static_cast<std::ptrdiff_t>(pos + n));
    pos += n;
  } while (pos < raw.size());
  std::uint32_t a = 1, b = 0;
  for (std::uint8_t c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  put_u32be(z, (b << 16) | a);

  std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<std::uint8_t> ihdr;
  put_u32be(ihdr, static_cast<std::uint32_t>(width));
  put_u32be(ihdr, static_cast<std::uint32_t>(height));
  ihdr.insert(ihdr.end(), {8, 6, 0, 0, 0});  // 8-bit, RGBA, deflate, no filter, no interlace
  png_chunk(png, "IHDR", ihdr);
  png_chunk(png, "IDAT", z);
  png_chunk(png, "IEND", {});
  return png;
}

void write_file(const std::filesystem::path& file, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

void write_file(const std::filesystem::path& file, const std::string& text) {
  write_file(file, std::vector<std::uint8_t>(text.begin(), text.end()));
}

std::filesystem::path make_temp_dir(const std::string& tag) {
  static std::atomic<int> counter{0};
  for (;;) {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("hrpp-" + tag + "-" + std::to_string(::getpid()) + "-" +
                      std::to_string(counter++));
    if (std::filesystem::create_directories(dir)) return dir;
  }
}

}  // namespace hrpp::test
