#include "gpu/storage_buffer.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <utility>

#include "common/error.h"
#include "gpu/vulkan_context.h"

namespace hrpp {
namespace {

// Host-visible memory the buffer accepts, best first: device-local and coherent (a GPU's BAR or
// unified memory; all of lavapipe's), coherent, then any host-visible type.
std::uint32_t pick_memory_type(VkPhysicalDevice pd, std::uint32_t allowed, bool* coherent) {
  VkPhysicalDeviceMemoryProperties mp;
  vkGetPhysicalDeviceMemoryProperties(pd, &mp);
  const VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
  const VkMemoryPropertyFlags kCoherent = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  const VkMemoryPropertyFlags kLocal = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
  const VkMemoryPropertyFlags wanted[] = {kHost | kCoherent | kLocal, kHost | kCoherent, kHost};
  for (VkMemoryPropertyFlags want : wanted)
    for (std::uint32_t i = 0; i < mp.memoryTypeCount; ++i)
      if ((allowed & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want) {
        *coherent = (mp.memoryTypes[i].propertyFlags & kCoherent) != 0;
        return i;
      }
  throw Error("the Vulkan device offers no host-visible memory for storage buffers");
}

}  // namespace

std::string format_bytes(std::uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f MiB", static_cast<double>(bytes) / (1024.0 * 1024.0));
  return buf;
}

StorageBuffer::StorageBuffer(VulkanContext& ctx, std::size_t bytes, std::string name)
    : device_(ctx.device()), bytes_(bytes), name_(std::move(name)) {
  const std::uint64_t limit = ctx.info().max_storage_buffer_range;
  if (bytes > limit)
    throw Error(name_ + " is " + format_bytes(bytes) + " (" + std::to_string(bytes) +
                " bytes), over the device's maxStorageBufferRange of " + format_bytes(limit) +
                " (" + std::to_string(limit) + " bytes)");
  const std::size_t alloc = std::max<std::size_t>(bytes, 16);  // Vulkan forbids size 0
  VkBufferCreateInfo bci{};
  bci.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  bci.size = alloc;
  // Texel-buffer use too: kernels may read an array through a TexelView (gpu/texel_view.h).
  bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
              VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
              VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
              VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check_vk(vkCreateBuffer(device_, &bci, nullptr, &buffer_), "vkCreateBuffer (" + name_ + ")");
  try {
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device_, buffer_, &req);
    VkMemoryAllocateInfo ai{};
    ai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = pick_memory_type(ctx.physical_device(), req.memoryTypeBits, &coherent_);
    check_vk(vkAllocateMemory(device_, &ai, nullptr, &memory_),
             "vkAllocateMemory (" + name_ + ", " + format_bytes(req.size) + ")");
    check_vk(vkBindBufferMemory(device_, buffer_, memory_, 0), "vkBindBufferMemory (" + name_ + ")");
    check_vk(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_),
             "vkMapMemory (" + name_ + ")");
  } catch (...) {
    release();
    throw;
  }
}

StorageBuffer::~StorageBuffer() { release(); }

StorageBuffer::StorageBuffer(StorageBuffer&& o) noexcept
    : device_(std::exchange(o.device_, VK_NULL_HANDLE)),
      buffer_(std::exchange(o.buffer_, VK_NULL_HANDLE)),
      memory_(std::exchange(o.memory_, VK_NULL_HANDLE)),
      mapped_(std::exchange(o.mapped_, nullptr)),
      coherent_(o.coherent_),
      bytes_(std::exchange(o.bytes_, 0)),
      name_(std::move(o.name_)) {}

StorageBuffer& StorageBuffer::operator=(StorageBuffer&& o) noexcept {
  if (this != &o) {
    release();
    device_ = std::exchange(o.device_, VK_NULL_HANDLE);
    buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
    mapped_ = std::exchange(o.mapped_, nullptr);
    coherent_ = o.coherent_;
    bytes_ = std::exchange(o.bytes_, 0);
    name_ = std::move(o.name_);
  }
  return *this;
}

void StorageBuffer::release() noexcept {
  if (mapped_) vkUnmapMemory(device_, memory_);
  if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
  if (memory_) vkFreeMemory(device_, memory_, nullptr);
  mapped_ = nullptr;
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
}

void StorageBuffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
  if (offset + bytes > bytes_)
    throw Error("upload of " + std::to_string(bytes) + " bytes overruns " + name_);
  if (bytes == 0) return;
  std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
  if (!coherent_) {
    VkMappedMemoryRange r{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_, 0, VK_WHOLE_SIZE};
    check_vk(vkFlushMappedMemoryRanges(device_, 1, &r), "vkFlushMappedMemoryRanges (" + name_ + ")");
  }
}

void StorageBuffer::download(void* out, std::size_t bytes, std::size_t offset) const {
  if (offset + bytes > bytes_)
    throw Error("download of " + std::to_string(bytes) + " bytes overruns " + name_);
  if (bytes == 0) return;
  if (!coherent_) {
    VkMappedMemoryRange r{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_, 0, VK_WHOLE_SIZE};
    check_vk(vkInvalidateMappedMemoryRanges(device_, 1, &r),
             "vkInvalidateMappedMemoryRanges (" + name_ + ")");
  }
  std::memcpy(out, static_cast<const char*>(mapped_) + offset, bytes);
}

void StorageBuffer::fill(std::uint32_t word) {
  auto* p = static_cast<std::uint32_t*>(mapped_);
  std::fill(p, p + bytes_ / 4, word);
  if (!coherent_) {
    VkMappedMemoryRange r{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_, 0, VK_WHOLE_SIZE};
    check_vk(vkFlushMappedMemoryRanges(device_, 1, &r), "vkFlushMappedMemoryRanges (" + name_ + ")");
  }
}

}  // namespace hrpp
