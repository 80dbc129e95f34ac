// glTF accessors read safely: every element checked to lie inside its buffer, integer components
// dequantized exactly as the glTF 2.0 spec says (3.11, KHR_mesh_quantization), sparse accessors
// (and accessors without a bufferView) made dense first.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace hrpp {

// A problem in a glTF file found by the decoding code; the loader prefixes the file name.
class GltfError : public std::runtime_error {
 public:
  explicit GltfError(const std::string& message) : std::runtime_error(message) {}
};

int gltf_component_size(int component_type);          // bytes; 0: invalid
const char* gltf_component_name(int component_type);  // "UNSIGNED_SHORT"
int gltf_type_components(int type);                   // VEC3: 3; 0: invalid
const char* gltf_type_name(int type);                 // "VEC3"

// A validated accessor: `count` elements of `components` components at base + i * stride.
struct AccessorView {
  const std::uint8_t* base = nullptr;
  std::size_t stride = 0;
  std::size_t count = 0;
  int component_type = 0;
  int components = 0;
  int type = 0;
  bool normalized = false;

  template <typename T>
  T load(std::size_t element, int component) const {
    T v;
    std::memcpy(&v, base + element * stride + component * sizeof(T), sizeof(T));
    return v;
  }
  // The component's value: a float as is; a normalized integer c as the spec maps it
  // (BYTE max(c / 127, -1), UNSIGNED_BYTE c / 255, SHORT max(c / 32767, -1),
  // UNSIGNED_SHORT c / 65535); any other integer as the number c.
  float read_float(std::size_t element, int component) const;
  std::uint32_t read_index(std::size_t element) const;  // an unsigned integer SCALAR
  // "normalized SHORT VEC3" for messages.
  std::string format() const;
};

// Views of a model's accessors. Keeps the dense copies of sparse accessors.
class AccessorReader {
 public:
  explicit AccessorReader(const tinygltf::Model& model) : m_(model) {}

  // Accessor `index`, used as `use` ("POSITION"); throws GltfError naming both.
  AccessorView view(int index, const std::string& use);
  // The bytes of bufferView `index` (checked to lie inside its buffer).
  const std::uint8_t* view_bytes(int index, std::size_t& size) const;

 private:
  static AccessorView described(const tinygltf::Accessor& acc);
  AccessorView buffer_view_elements(int index, const std::string& where) const;
  void check_range(int index, const AccessorView& v, std::size_t element) const;
  AccessorView dense(int index, const std::string& where);
  void apply_sparse(const tinygltf::Accessor& acc, const std::string& where,
                    std::vector<std::uint8_t>& out, std::size_t element) const;

  const tinygltf::Model& m_;
  std::map<int, std::vector<std::uint8_t>> dense_;  // accessor -> its elements, tightly packed
};

}  // namespace hrpp
