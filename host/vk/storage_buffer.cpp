#include "vk/storage_buffer.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "common/bytes.h"
#include "common/error.h"
#include "vk/staged_transfer.h"
#include "vk/vulkan_context.h"

namespace hrpp {
StorageBuffer::StorageBuffer(VulkanContext& ctx, std::size_t bytes, std::string name,
                             BufferBinding binding, MemoryRole role)
    : device_(ctx.device()), bytes_(bytes), name_(std::move(name)), binding_(binding) {
  const MemoryLimits limits = memory_limits(ctx.info());
  check_buffer(BufferNeed{name_, bytes, binding}, limits);
  // Buffers made after the scene's check (arrays that grow with a batch) still fit the heap
  // (the device role's; host-shared buffers, the staging buffer among them, are host memory
  // on a discrete GPU, and a few KiB besides it).
  const std::uint64_t held = ctx.memory().total();
  if (role == MemoryRole::kDevice && held + bytes > limits.heap)
    throw Error(name_ + " (" + format_bytes(bytes) + ") does not fit beside the " +
                format_bytes(held) + " already allocated in the device's " + limits.heap_name +
                " of " + format_bytes(limits.heap) + " (" + std::to_string(limits.heap) +
                " bytes)");
  const std::size_t alloc = std::max<std::size_t>(bytes, 16);  // Vulkan forbids size 0
  VkBufferCreateInfo bci{};
  bci.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  bci.size = alloc;
  // Texel-buffer use too: kernels may read an array through a TexelView (vk/texel_view.h).
  bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
              VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
              VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
              VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  if (ctx.ray_queries())  // an acceleration structure's input, storage or scratch
    bci.usage |= VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                 VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
                 VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check_vk(vkCreateBuffer(device_, &bci, nullptr, &buffer_), "vkCreateBuffer (" + name_ + ")");
  try {
    allocate(ctx, role);
  } catch (...) {
    release();
    throw;
  }
}

// Memory of the type the role takes under the context's mode, bound, and mapped or staged.
void StorageBuffer::allocate(VulkanContext& ctx, MemoryRole role) {
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device_, buffer_, &req);
  VkPhysicalDeviceMemoryProperties mp;
  vkGetPhysicalDeviceMemoryProperties(ctx.physical_device(), &mp);
  const MemoryTypeChoice type =
      choose_memory_type(mp, req.memoryTypeBits, ctx.info().memory_mode, role);
  coherent_ = type.coherent();
  VkMemoryAllocateInfo ai{};
  ai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = type.type;
  VkMemoryAllocateFlagsInfo flags{};
  flags.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO;
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  if (ctx.ray_queries()) ai.pNext = &flags;
  check_vk(vkAllocateMemory(device_, &ai, nullptr, &memory_),
           "vkAllocateMemory (" + name_ + ", " + format_bytes(req.size) + ")");
  ledger_ = &ctx.memory();
  allocated_ = req.size;
  ledger_->add(name_, allocated_);
  check_vk(vkBindBufferMemory(device_, buffer_, memory_, 0), "vkBindBufferMemory (" + name_ + ")");
  if (ctx.ray_queries()) {
    VkBufferDeviceAddressInfo bai{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO, nullptr, buffer_};
    address_ = vkGetBufferDeviceAddress(device_, &bai);
  }
  if (!type.mapped) {
    staging_ = ctx.staging();
    return;
  }
  check_vk(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_),
           "vkMapMemory (" + name_ + ")");
}

StorageBuffer::~StorageBuffer() { release(); }

StorageBuffer::StorageBuffer(StorageBuffer&& o) noexcept
    : device_(std::exchange(o.device_, VK_NULL_HANDLE)),
      buffer_(std::exchange(o.buffer_, VK_NULL_HANDLE)),
      memory_(std::exchange(o.memory_, VK_NULL_HANDLE)),
      mapped_(std::exchange(o.mapped_, nullptr)),
      staging_(std::exchange(o.staging_, nullptr)),
      coherent_(o.coherent_),
      bytes_(std::exchange(o.bytes_, 0)),
      name_(std::move(o.name_)),
      binding_(o.binding_),
      ledger_(std::exchange(o.ledger_, nullptr)),
      allocated_(std::exchange(o.allocated_, 0)),
      address_(std::exchange(o.address_, 0)) {}

StorageBuffer& StorageBuffer::operator=(StorageBuffer&& o) noexcept {
  if (this != &o) {
    release();
    device_ = std::exchange(o.device_, VK_NULL_HANDLE);
    buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
    mapped_ = std::exchange(o.mapped_, nullptr);
    staging_ = std::exchange(o.staging_, nullptr);
    coherent_ = o.coherent_;
    bytes_ = std::exchange(o.bytes_, 0);
    name_ = std::move(o.name_);
    binding_ = o.binding_;
    ledger_ = std::exchange(o.ledger_, nullptr);
    allocated_ = std::exchange(o.allocated_, 0);
    address_ = std::exchange(o.address_, 0);
  }
  return *this;
}

void StorageBuffer::release() noexcept {
  if (mapped_) vkUnmapMemory(device_, memory_);
  if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
  if (memory_) vkFreeMemory(device_, memory_, nullptr);
  if (ledger_) ledger_->remove(name_, allocated_);
  ledger_ = nullptr;
  allocated_ = 0;
  address_ = 0;
  mapped_ = nullptr;
  staging_ = nullptr;
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
}

void StorageBuffer::check_range(const char* what, std::size_t bytes, std::size_t offset) const {
  if (offset + bytes > bytes_)
    throw Error(std::string(what) + " of " + std::to_string(bytes) + " bytes overruns " + name_);
}

void StorageBuffer::flush() const {
  if (coherent_) return;
  VkMappedMemoryRange r{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_, 0, VK_WHOLE_SIZE};
  check_vk(vkFlushMappedMemoryRanges(device_, 1, &r), "vkFlushMappedMemoryRanges (" + name_ + ")");
}

void StorageBuffer::invalidate() const {
  if (coherent_) return;
  VkMappedMemoryRange r{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_, 0, VK_WHOLE_SIZE};
  check_vk(vkInvalidateMappedMemoryRanges(device_, 1, &r),
           "vkInvalidateMappedMemoryRanges (" + name_ + ")");
}

void StorageBuffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
  check_range("upload", bytes, offset);
  if (bytes == 0) return;
  if (staging_) return staging_->upload(buffer_, offset, data, bytes, name_);
  std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
  flush();
}

void StorageBuffer::download(void* out, std::size_t bytes, std::size_t offset) const {
  check_range("download", bytes, offset);
  if (bytes == 0) return;
  if (staging_) return staging_->download(buffer_, offset, out, bytes, name_);
  invalidate();
  std::memcpy(out, static_cast<const char*>(mapped_) + offset, bytes);
}

void StorageBuffer::fill(std::uint32_t word) {
  if (staging_) return staging_->fill(buffer_, bytes_, word, name_);
  auto* p = static_cast<std::uint32_t*>(mapped_);
  std::fill(p, p + bytes_ / 4, word);
  flush();
}

}  // namespace hrpp
