// The copies of a staged buffer (--memory staged, vk/memory_placement.h): upload, download and
// fill of a device-local VkBuffer through one host-visible staging buffer, in chunks of
// kChunkBytes, each a one-time command buffer on the context's queue waited on with its fence,
// so the callers keep their synchronous semantics. Barriers: earlier shader writes, indirect
// reads and transfers before the copy; the copy before later shader reads and writes, indirect
// reads and transfers, and (VulkanContext::submit_and_wait) before the host's reads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include <vulkan/vulkan.h>

#include "vk/storage_buffer.h"

namespace hrpp {

class VulkanContext;

class StagedTransfer {
 public:
  static constexpr std::size_t kChunkBytes = std::size_t{8} << 20;

  // Records, submits and waits (VulkanContext::submit_and_wait).
  using Submit = std::function<void(const std::function<void(VkCommandBuffer)>& record,
                                    const std::string& what)>;

  // Allocates the staging buffer (kChunkBytes, role kHostShared) in `ctx`.
  StagedTransfer(VulkanContext& ctx, Submit submit);

  // `name`: the device buffer's, for errors.
  void upload(VkBuffer dst, std::size_t offset, const void* data, std::size_t bytes,
              const std::string& name);
  void download(VkBuffer src, std::size_t offset, void* out, std::size_t bytes,
                const std::string& name);
  void fill(VkBuffer dst, std::size_t bytes, std::uint32_t word, const std::string& name);

 private:
  // One command buffer: barrier, what `copy` records, barrier.
  void run(const std::function<void(VkCommandBuffer)>& copy, const std::string& what);

  Submit submit_;
  StorageBuffer staging_;
};

}  // namespace hrpp
