// Descriptor types of the trace kernels' bindings (shaders/shared/trace_interface.h; the indexed
// ones add the ray index list, the skipping ones the skip lists, texel buffers) and of the HRPP
// stage's (shaders/shared/hrpp_interface.h): the BVH arrays and the rays are uniform texel buffers
// (bindings 0..5); the stage also reads and writes its per-ray arrays as texel buffers
// (shaders/lib/hrpp_stage.glsl); everything else is a storage buffer. And the trace kernels'
// names per query kind.
#pragma once

#include <array>
#include <cstddef>

#include <vulkan/vulkan.h>

#include "hrpp_interface.h"
#include "kernel_names.h"
#include "trace/query_kind.h"
#include "trace_interface.h"

namespace hrpp {

template <std::size_t N>
constexpr std::array<VkDescriptorType, N> texel_then_storage_bindings() {
  std::array<VkDescriptorType, N> t{};
  t.fill(VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  t[HRPP_TRACE_BINDING_NODES] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  t[HRPP_TRACE_BINDING_LEAVES] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  for (int k = 0; k < HRPP_TRACE_TRIANGLE_PLANES; ++k)
    t[HRPP_TRACE_BINDING_TRIANGLES + k] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  t[HRPP_TRACE_BINDING_RAYS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  return t;
}

inline constexpr auto kTraceBindingTypes = [] {
  auto t = texel_then_storage_bindings<HRPP_TRACE_BINDING_COUNT>();
  t[HRPP_TRACE_BINDING_HITS] = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
  return t;
}();
// The ray-query kernels: the top-level acceleration structure, then as the trace kernels' rays,
// hits and counters.
inline constexpr std::array<VkDescriptorType, HRPP_RAY_QUERY_BINDING_COUNT> kRayQueryBindingTypes =
    {VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
     VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
static_assert(HRPP_RAY_QUERY_BINDING_SCENE == 0 && HRPP_RAY_QUERY_BINDING_RAYS == 1 &&
              HRPP_RAY_QUERY_BINDING_HITS == 2 && HRPP_RAY_QUERY_BINDING_COUNTERS == 3);
// The indexed and the skipping trace kernels: the trace kernels' bindings and one list read per
// position (the ray index list or the skip lists), a texel view.
inline constexpr auto kTraceListBindingTypes = [] {
  std::array<VkDescriptorType, HRPP_TRACE_INDEXED_BINDING_COUNT> t{};
  for (std::size_t i = 0; i < kTraceBindingTypes.size(); ++i) t[i] = kTraceBindingTypes[i];
  t[HRPP_TRACE_BINDING_RAY_INDICES] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  return t;
}();
static_assert(HRPP_TRACE_BINDING_RAY_INDICES == HRPP_TRACE_BINDING_COUNT);
static_assert(HRPP_TRACE_BINDING_SKIP_NODES == HRPP_TRACE_BINDING_RAY_INDICES &&
              HRPP_TRACE_SKIPPING_BINDING_COUNT == HRPP_TRACE_INDEXED_BINDING_COUNT);
inline constexpr auto kStageBindingTypes = [] {
  auto t = texel_then_storage_bindings<HRPP_STAGE_BINDING_COUNT>();
  t[HRPP_STAGE_BINDING_HITS] = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
  t[HRPP_STAGE_BINDING_QUEUE_RAYS] = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
  t[HRPP_STAGE_BINDING_QUEUE_ENTRIES] = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
  t[HRPP_STAGE_BINDING_QUEUE_HITS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  t[HRPP_STAGE_BINDING_TAG_TEXELS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  t[HRPP_STAGE_BINDING_SLOT_TEXELS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  t[HRPP_STAGE_BINDING_NODE_OF_PRIM] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  t[HRPP_STAGE_BINDING_QUEUE_SKIPS] = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
  return t;
}();
static_assert(HRPP_STAGE_BINDING_HITS == HRPP_TRACE_BINDING_HITS);

// The trace kernel of a query kind (shaders/trace_closest.comp, shaders/trace_any.comp), its
// indexed variant (trace_*_indexed.comp) and its skipping one (trace_*_skipping.comp).
constexpr Kernel trace_kernel(QueryKind k) {
  return k == QueryKind::kAny ? Kernel::trace_any : Kernel::trace_closest;
}
constexpr Kernel ray_query_kernel(QueryKind k) {
  return k == QueryKind::kAny ? Kernel::trace_rayquery_any : Kernel::trace_rayquery_closest;
}
constexpr Kernel trace_indexed_kernel(QueryKind k) {
  return k == QueryKind::kAny ? Kernel::trace_any_indexed : Kernel::trace_closest_indexed;
}
constexpr Kernel trace_skipping_kernel(QueryKind k) {
  return k == QueryKind::kAny ? Kernel::trace_any_skipping : Kernel::trace_closest_skipping;
}

}  // namespace hrpp
