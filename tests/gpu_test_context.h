// The Vulkan context of a GPU test binary: one for the whole binary, validated (the Khronos
// layer on; its messages are counted, and the tests check validation_messages() == 0), made on
// first use and kept to the end, so each pipeline JIT-compiles once per binary.
#pragma once

#include "vk/vulkan_context.h"

namespace hrpp::test {

inline VulkanContext& context() {
  static auto* ctx = new VulkanContext(VulkanOptions{"", true});
  return *ctx;
}

}  // namespace hrpp::test
