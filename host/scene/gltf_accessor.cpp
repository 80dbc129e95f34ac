#include "scene/gltf_accessor.h"

#include <algorithm>
#include <type_traits>

namespace hrpp {
namespace {

// A sparse accessor's byteOffset is an int in tinygltf 2.7 (Debian 12) and a size_t in 2.9
// (Debian 13): only the signed one can be negative.
template <class T>
bool is_negative(T offset) {
  if constexpr (std::is_signed_v<T>)
    return offset < 0;
  else
    return false;
}

// An accessor without a bufferView (sparse over zeros) holds at most this many bytes.
constexpr std::size_t kMaxDenseBytes = std::size_t{1} << 28;

std::string str(std::size_t v) { return std::to_string(v); }

// A component type (size: bytes) or an element type (size: components), and its name.
struct TypeInfo {
  int id, size;
  const char* name;
};
constexpr TypeInfo kComponentTypes[] = {
    {TINYGLTF_COMPONENT_TYPE_BYTE, 1, "BYTE"},
    {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, 1, "UNSIGNED_BYTE"},
    {TINYGLTF_COMPONENT_TYPE_SHORT, 2, "SHORT"},
    {TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, 2, "UNSIGNED_SHORT"},
    {TINYGLTF_COMPONENT_TYPE_INT, 4, "INT"},
    {TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, 4, "UNSIGNED_INT"},
    {TINYGLTF_COMPONENT_TYPE_FLOAT, 4, "FLOAT"}};
constexpr TypeInfo kElementTypes[] = {
    {TINYGLTF_TYPE_SCALAR, 1, "SCALAR"}, {TINYGLTF_TYPE_VEC2, 2, "VEC2"},
    {TINYGLTF_TYPE_VEC3, 3, "VEC3"},     {TINYGLTF_TYPE_VEC4, 4, "VEC4"},
    {TINYGLTF_TYPE_MAT2, 4, "MAT2"},     {TINYGLTF_TYPE_MAT3, 9, "MAT3"},
    {TINYGLTF_TYPE_MAT4, 16, "MAT4"}};

// The entry of `id`; size 0 and name "invalid" when there is none.
template <std::size_t N>
TypeInfo find_id(const TypeInfo (&table)[N], int id) {
  for (const TypeInfo& e : table) {
    if (e.id == id) return e;
  }
  return {id, 0, "invalid"};
}

// a + b <= limit, without overflow.
bool fits(std::size_t a, std::size_t b, std::size_t limit) {
  std::size_t end = 0;
  return !__builtin_add_overflow(a, b, &end) && end <= limit;
}

}  // namespace

int gltf_component_size(int component_type) {
  return find_id(kComponentTypes, component_type).size;
}
const char* gltf_component_name(int component_type) {
  return find_id(kComponentTypes, component_type).name;
}
int gltf_type_components(int type) { return find_id(kElementTypes, type).size; }
const char* gltf_type_name(int type) { return find_id(kElementTypes, type).name; }

float AccessorView::read_float(std::size_t element, int component) const {
  auto integer = [&](float c, float scale) { return normalized ? std::max(c / scale, -1.0f) : c; };
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return load<float>(element, component);
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return integer(load<std::int8_t>(element, component), 127.0f);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return integer(load<std::uint8_t>(element, component), 255.0f);
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return integer(load<std::int16_t>(element, component), 32767.0f);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return integer(load<std::uint16_t>(element, component), 65535.0f);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return static_cast<float>(load<std::uint32_t>(element, component));
    default:
      return 0.0f;
  }
}

std::uint32_t AccessorView::read_index(std::size_t element) const {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return load<std::uint8_t>(element, 0);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return load<std::uint16_t>(element, 0);
    default:
      return load<std::uint32_t>(element, 0);
  }
}

std::string AccessorView::format() const {
  return std::string(normalized ? "normalized " : "") + gltf_component_name(component_type) + " " +
         gltf_type_name(type);
}

const std::uint8_t* AccessorReader::view_bytes(int index, std::size_t& size) const {
  if (index < 0 || static_cast<std::size_t>(index) >= m_.bufferViews.size()) {
    throw GltfError("bufferView " + std::to_string(index) + " does not exist");
  }
  const tinygltf::BufferView& bv = m_.bufferViews[index];
  if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= m_.buffers.size()) {
    throw GltfError("bufferView " + std::to_string(index) + ": buffer " +
                    std::to_string(bv.buffer) + " does not exist");
  }
  const std::vector<unsigned char>& data = m_.buffers[bv.buffer].data;
  if (!fits(bv.byteOffset, bv.byteLength, data.size())) {
    throw GltfError("bufferView " + std::to_string(index) + " lies past the end of buffer " +
                    std::to_string(bv.buffer));
  }
  size = bv.byteLength;
  return data.data() + bv.byteOffset;
}

AccessorView AccessorReader::view(int index, const std::string& use) {
  if (index < 0 || static_cast<std::size_t>(index) >= m_.accessors.size()) {
    throw GltfError(use + ": accessor " + std::to_string(index) + " does not exist");
  }
  const std::string where = "accessor " + std::to_string(index) + " (" + use + ")";
  const tinygltf::Accessor& acc = m_.accessors[index];
  if (gltf_component_size(acc.componentType) == 0) {
    throw GltfError(where + ": invalid componentType " + std::to_string(acc.componentType));
  }
  if (gltf_type_components(acc.type) == 0) throw GltfError(where + ": invalid type");
  if (acc.sparse.isSparse) return dense(index, where);
  return buffer_view_elements(index, where);
}

// The accessor's format, tightly packed (stride: the element size), no data yet.
AccessorView AccessorReader::described(const tinygltf::Accessor& acc) {
  AccessorView v;
  v.count = acc.count;
  v.component_type = acc.componentType;
  v.components = gltf_type_components(acc.type);
  v.type = acc.type;
  v.normalized = acc.normalized;
  v.stride = static_cast<std::size_t>(gltf_component_size(acc.componentType)) * v.components;
  return v;
}

// The accessor's elements in its bufferView (sparse substitution not applied).
AccessorView AccessorReader::buffer_view_elements(int index, const std::string& where) const {
  const tinygltf::Accessor& acc = m_.accessors[index];
  AccessorView v = described(acc);
  const std::size_t element = v.stride;
  if (acc.bufferView < 0 || static_cast<std::size_t>(acc.bufferView) >= m_.bufferViews.size()) {
    throw GltfError(where + ": bufferView " + std::to_string(acc.bufferView) + " does not exist");
  }
  const tinygltf::BufferView& bv = m_.bufferViews[acc.bufferView];
  v.stride = bv.byteStride != 0 ? bv.byteStride : element;
  if (v.stride < element) {
    throw GltfError(where + ": byteStride " + std::to_string(bv.byteStride) +
                    " is smaller than the element size " + str(element));
  }
  if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= m_.buffers.size()) {
    throw GltfError("bufferView " + std::to_string(acc.bufferView) + ": buffer " +
                    std::to_string(bv.buffer) + " does not exist");
  }
  const std::vector<unsigned char>& data = m_.buffers[bv.buffer].data;
  v.base = data.data();
  if (v.count == 0) return v;  // nothing is read
  check_range(index, v, element);
  v.base += bv.byteOffset + acc.byteOffset;
  return v;
}

// Every byte accessor `index` (view v, elements of `element` bytes) reads lies in its bufferView
// and the bufferView in its buffer.
void AccessorReader::check_range(int index, const AccessorView& v, std::size_t element) const {
  const tinygltf::Accessor& acc = m_.accessors[index];
  const tinygltf::BufferView& bv = m_.bufferViews[acc.bufferView];
  const std::vector<unsigned char>& data = m_.buffers[bv.buffer].data;
  // Bytes the accessor reads, relative to the view: byteOffset + stride*(count-1) + element.
  std::size_t span = 0, in_view_end = 0, abs_end = 0;
  const bool overflow = __builtin_mul_overflow(v.stride, v.count - 1, &span) ||
                        __builtin_add_overflow(span, element, &span) ||
                        __builtin_add_overflow(span, acc.byteOffset, &in_view_end) ||
                        __builtin_add_overflow(in_view_end, bv.byteOffset, &abs_end);
  if (overflow || abs_end > data.size()) {
    throw GltfError("accessor " + std::to_string(index) + " reads past the end of buffer " +
                    std::to_string(bv.buffer));
  }
  if (!fits(bv.byteOffset, bv.byteLength, data.size())) {
    throw GltfError("bufferView " + std::to_string(acc.bufferView) +
                    " lies past the end of buffer " + std::to_string(bv.buffer));
  }
  if (in_view_end > bv.byteLength) {
    throw GltfError("accessor " + std::to_string(index) + " reads past the end of bufferView " +
                    std::to_string(acc.bufferView));
  }
}

// A sparse accessor as a dense, tightly packed copy: its bufferView's elements (zeros without
// one) with the sparse elements substituted.
AccessorView AccessorReader::dense(int index, const std::string& where) {
  const tinygltf::Accessor& acc = m_.accessors[index];
  AccessorView v = described(acc);
  const std::size_t element = v.stride;
  auto cached = dense_.find(index);
  if (cached == dense_.end()) {
    std::vector<std::uint8_t> out;
    if (acc.bufferView >= 0) {
      const AccessorView base = buffer_view_elements(index, where);
      out.resize(base.count * element);
      for (std::size_t i = 0; i < base.count; ++i) {
        std::memcpy(out.data() + i * element, base.base + i * base.stride, element);
      }
    } else {
      if (acc.count > kMaxDenseBytes / element) {
        throw GltfError(where + ": " + str(acc.count) + " elements without a bufferView");
      }
      out.assign(acc.count * element, 0);
    }
    apply_sparse(acc, where, out, element);
    cached = dense_.emplace(index, std::move(out)).first;
  }
  v.base = cached->second.data();
  return v;
}

void AccessorReader::apply_sparse(const tinygltf::Accessor& acc, const std::string& where,
                                  std::vector<std::uint8_t>& out, std::size_t element) const {
  const auto& sp = acc.sparse;
  if (sp.count < 1 || static_cast<std::size_t>(sp.count) > acc.count) {
    throw GltfError(where + ": sparse count " + std::to_string(sp.count) + " is not in 1.." +
                    str(acc.count));
  }
  const int isize = gltf_component_size(sp.indices.componentType);
  if (sp.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      sp.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      sp.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    throw GltfError(where + ": sparse indices componentType " +
                    std::to_string(sp.indices.componentType) + " is not an unsigned integer");
  }
  const std::size_t n = static_cast<std::size_t>(sp.count);
  std::size_t index_bytes = 0, value_bytes = 0;
  const std::uint8_t* indices = view_bytes(sp.indices.bufferView, index_bytes);
  const std::uint8_t* values = view_bytes(sp.values.bufferView, value_bytes);
  if (is_negative(sp.indices.byteOffset) || is_negative(sp.values.byteOffset) ||
      !fits(static_cast<std::size_t>(sp.indices.byteOffset), n * isize, index_bytes) ||
      !fits(static_cast<std::size_t>(sp.values.byteOffset), n * element, value_bytes)) {
    throw GltfError(where + ": sparse indices or values lie past the end of their bufferView");
  }
  AccessorView idx;
  idx.base = indices + sp.indices.byteOffset;
  idx.stride = static_cast<std::size_t>(isize);
  idx.count = n;
  idx.component_type = sp.indices.componentType;
  values += sp.values.byteOffset;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t target = idx.read_index(i);
    if (target >= acc.count) {
      throw GltfError(where + ": sparse index " + std::to_string(target) + " is out of range");
    }
    std::memcpy(out.data() + target * element, values + i * element, element);
  }
}

}  // namespace hrpp
