#include "vk/texel_view.h"

#include <string>
#include <utility>

#include "common/error.h"
#include "vk/storage_buffer.h"
#include "vk/vulkan_context.h"

namespace hrpp {

TexelView::TexelView(VulkanContext& ctx, const StorageBuffer& buffer) : device_(ctx.device()) {
  // An empty array still has a 16-byte buffer (StorageBuffer never creates size 0): one texel.
  const std::size_t bytes = buffer.size() == 0 ? kTexelBytes : buffer.size();
  if (bytes % kTexelBytes != 0)
    throw Error(buffer.name() + " is " + std::to_string(bytes) +
                " bytes, not a whole number of 16-byte texels");
  const std::uint64_t texels = bytes / kTexelBytes;
  const std::uint64_t limit = ctx.info().max_texel_buffer_elements;
  if (texels > limit)
    throw Error(buffer.name() + " is " + std::to_string(texels) +
                " 16-byte texels, over the device's maxTexelBufferElements of " +
                std::to_string(limit));
  VkBufferViewCreateInfo ci{};
  ci.sType = VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO;
  ci.buffer = buffer.handle();
  ci.format = kFormat;
  ci.offset = 0;
  ci.range = bytes;
  check_vk(vkCreateBufferView(device_, &ci, nullptr, &view_),
           "vkCreateBufferView (" + buffer.name() + ")");
}

TexelView::~TexelView() {
  if (view_) vkDestroyBufferView(device_, view_, nullptr);
}

TexelView::TexelView(TexelView&& o) noexcept
    : device_(std::exchange(o.device_, VK_NULL_HANDLE)),
      view_(std::exchange(o.view_, VK_NULL_HANDLE)) {}

TexelView& TexelView::operator=(TexelView&& o) noexcept {
  if (this != &o) {
    if (view_) vkDestroyBufferView(device_, view_, nullptr);
    device_ = std::exchange(o.device_, VK_NULL_HANDLE);
    view_ = std::exchange(o.view_, VK_NULL_HANDLE);
  }
  return *this;
}

}  // namespace hrpp
