// A uniform texel buffer view over a whole StorageBuffer: 16-byte texels in
// VK_FORMAT_R32G32B32A32_UINT, read by a kernel as `utextureBuffer` with samplerless texelFetch,
// bit for bit (an integer format: no conversion, NaN payloads and denormals intact).
//
// Why: on lavapipe (llvmpipe) a storage-buffer load with a different address per lane is a loop
// over the lanes inserting one 32-bit word at a time through the stack, while a texel fetch
// gathers the lanes' 16-byte texels in one vector operation; the trace kernels' node and triangle
// fetches run several times faster this way (DECISIONS.md). Move-only.
#pragma once

#include <vulkan/vulkan.h>

namespace hrpp {

class VulkanContext;
class StorageBuffer;

class TexelView {
 public:
  static constexpr VkFormat kFormat = VK_FORMAT_R32G32B32A32_UINT;
  static constexpr unsigned kTexelBytes = 16;

  TexelView() = default;
  // Throws hrpp::Error (naming the buffer) when its size is not a whole number of texels or its
  // texels exceed the device's maxTexelBufferElements.
  TexelView(VulkanContext& ctx, const StorageBuffer& buffer);
  ~TexelView();
  TexelView(TexelView&& o) noexcept;
  TexelView& operator=(TexelView&& o) noexcept;
  TexelView(const TexelView&) = delete;
  TexelView& operator=(const TexelView&) = delete;

  VkBufferView handle() const { return view_; }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkBufferView view_ = VK_NULL_HANDLE;
};

}  // namespace hrpp
