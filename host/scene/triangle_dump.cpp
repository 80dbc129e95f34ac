// Triangle dump (docs/FORMATS.md): 9 × float32 per triangle (v0, v1, v2), little-endian,
// triangle-id order.
#include <bit>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "common/error.h"
#include "scene/load_scene.h"

namespace hrpp {

void write_triangle_dump(const Scene& scene, const std::filesystem::path& file) {
  const std::string name = file.string();
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(name.c_str(), "wb"), &std::fclose);
  if (!f) throw Error(name + ": cannot open for writing: " + std::strerror(errno));
  constexpr std::size_t kChunk = 1 << 14;  // triangles per write
  std::vector<std::uint32_t> words;
  words.reserve(kChunk * 9);
  auto flush = [&]() {
    if (words.empty()) return;
    if (std::fwrite(words.data(), sizeof(std::uint32_t), words.size(), f.get()) != words.size()) {
      throw Error(name + ": write failed: " + std::strerror(errno));
    }
    words.clear();
  };
  for (const Triangle& t : scene.triangles) {
    for (const glm::vec3& v : {t.v0, t.v1, t.v2}) {
      for (int c = 0; c < 3; ++c) {
        std::uint32_t w = std::bit_cast<std::uint32_t>(v[c]);
        if constexpr (std::endian::native == std::endian::big) w = __builtin_bswap32(w);
        words.push_back(w);
      }
    }
    if (words.size() >= kChunk * 9) flush();
  }
  flush();
  if (std::fflush(f.get()) != 0) throw Error(name + ": write failed: " + std::strerror(errno));
  std::FILE* raw = f.release();
  if (std::fclose(raw) != 0) throw Error(name + ": write failed: " + std::strerror(errno));
}

}  // namespace hrpp
