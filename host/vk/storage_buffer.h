// A storage buffer in the memory its role takes under the context's memory mode
// (vk/memory_placement.h): mapped for its whole life, where upload, download and fill are memcpy
// (plus flush/invalidate on non-coherent memory), or staged in device-local memory, where they
// are copies through the context's staging buffer (vk/staged_transfer.h), as synchronous as
// memcpy. Move-only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include <vulkan/vulkan.h>

#include "vk/memory_placement.h"
#include "vk/memory_plan.h"

namespace hrpp {

class VulkanContext;
class MemoryLedger;
class StagedTransfer;

class StorageBuffer {
 public:
  StorageBuffer() = default;
  // `name` says what the array is in errors and in the context's memory ledger. `binding`: how
  // the kernels see it; a kTexelOnly buffer is read through TexelViews only, so its limit is
  // maxTexelBufferElements, not maxStorageBufferRange (vk/memory_plan.h), and
  // ComputePipeline refuses to bind it as a storage buffer. Throws hrpp::Error when `bytes`
  // exceeds the limit of its binding (naming the array and the limit), when it would take the
  // context's buffers past the device's heap (DeviceInfo::heap_bytes), or memory runs out.
  // `role`: which memory type it gets (kHostShared: mapped in every mode, and not checked
  // against the heap, which is the device role's).
  StorageBuffer(VulkanContext& ctx, std::size_t bytes, std::string name,
                BufferBinding binding = BufferBinding::kStorage,
                MemoryRole role = MemoryRole::kDevice);
  StorageBuffer(VulkanContext& ctx, const BufferNeed& need, MemoryRole role = MemoryRole::kDevice)
      : StorageBuffer(ctx, need.bytes, need.name, need.binding, role) {}
  ~StorageBuffer();
  StorageBuffer(StorageBuffer&& o) noexcept;
  StorageBuffer& operator=(StorageBuffer&& o) noexcept;
  StorageBuffer(const StorageBuffer&) = delete;
  StorageBuffer& operator=(const StorageBuffer&) = delete;

  // A staged buffer's upload, download and fill submit and wait on the context's queue: not
  // while a command buffer is being recorded (VulkanContext::submit_and_wait throws then).
  void upload(const void* data, std::size_t bytes, std::size_t offset = 0);
  void download(void* out, std::size_t bytes, std::size_t offset = 0) const;
  void fill(std::uint32_t word);  // every 32-bit word of the buffer

  template <class T>
  void upload(std::span<const T> items) {
    upload(items.data(), items.size_bytes());
  }
  template <class T>
  void download(std::span<T> items) const {
    download(items.data(), items.size_bytes());
  }

  VkBuffer handle() const { return buffer_; }
  // The buffer's device address (0 unless the context has ray queries on: VulkanContext::
  // ray_queries(), where every buffer may feed or hold an acceleration structure).
  VkDeviceAddress device_address() const { return address_; }
  std::size_t size() const { return bytes_; }
  const std::string& name() const { return name_; }
  BufferBinding binding() const { return binding_; }

 private:
  void release() noexcept;
  void allocate(VulkanContext& ctx, MemoryRole role);
  void check_range(const char* what, std::size_t bytes, std::size_t offset) const;
  void flush() const;       // host writes → device (non-coherent memory only)
  void invalidate() const;  // device writes → host (non-coherent memory only)

  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;             // mapped memory, or nullptr when staged
  StagedTransfer* staging_ = nullptr;  // the context's, when staged
  bool coherent_ = true;
  std::size_t bytes_ = 0;
  std::string name_;
  BufferBinding binding_ = BufferBinding::kStorage;
  MemoryLedger* ledger_ = nullptr;  // the context's, while memory is allocated
  std::uint64_t allocated_ = 0;     // bytes of memory_, as the ledger has them
  VkDeviceAddress address_ = 0;
};


}  // namespace hrpp
