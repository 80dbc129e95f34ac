#include "vk/staged_transfer.h"

#include <algorithm>
#include <utility>

namespace hrpp {

namespace {

// The accesses a staged copy orders itself against, before and after: kernels (storage and
// texel reads and writes), indirect dispatch arguments, and other transfers.
constexpr VkPipelineStageFlags kWorkStages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                                             VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                                             VK_PIPELINE_STAGE_TRANSFER_BIT;
constexpr VkAccessFlags kWorkAccess = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                                      VK_ACCESS_INDIRECT_COMMAND_READ_BIT |
                                      VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
constexpr VkAccessFlags kWrites = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;

void barrier(VkCommandBuffer cmd, VkPipelineStageFlags src_stages, VkAccessFlags src,
             VkPipelineStageFlags dst_stages, VkAccessFlags dst) {
  VkMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  b.srcAccessMask = src;
  b.dstAccessMask = dst;
  vkCmdPipelineBarrier(cmd, src_stages, dst_stages, 0, 1, &b, 0, nullptr, 0, nullptr);
}

}  // namespace

StagedTransfer::StagedTransfer(VulkanContext& ctx, Submit submit)
    : submit_(std::move(submit)),
      staging_(ctx, kChunkBytes, "staging buffer", BufferBinding::kStorage,
               MemoryRole::kHostShared) {}

void StagedTransfer::run(const std::function<void(VkCommandBuffer)>& copy,
                         const std::string& what) {
  submit_(
      [&](VkCommandBuffer cmd) {
        barrier(cmd, kWorkStages, kWrites, VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
        copy(cmd);
        barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kWorkStages,
                kWorkAccess);
      },
      what);
}

void StagedTransfer::upload(VkBuffer dst, std::size_t offset, const void* data, std::size_t bytes,
                            const std::string& name) {
  for (std::size_t done = 0; done < bytes; done += kChunkBytes) {
    const std::size_t n = std::min(kChunkBytes, bytes - done);
    staging_.upload(static_cast<const char*>(data) + done, n);
    const VkBufferCopy region{0, offset + done, n};
    run([&](VkCommandBuffer cmd) { vkCmdCopyBuffer(cmd, staging_.handle(), dst, 1, &region); },
        "staged upload (" + name + ")");
  }
}

void StagedTransfer::download(VkBuffer src, std::size_t offset, void* out, std::size_t bytes,
                              const std::string& name) {
  for (std::size_t done = 0; done < bytes; done += kChunkBytes) {
    const std::size_t n = std::min(kChunkBytes, bytes - done);
    const VkBufferCopy region{offset + done, 0, n};
    run([&](VkCommandBuffer cmd) { vkCmdCopyBuffer(cmd, src, staging_.handle(), 1, &region); },
        "staged download (" + name + ")");
    staging_.download(static_cast<char*>(out) + done, n);
  }
}

void StagedTransfer::fill(VkBuffer dst, std::size_t bytes, std::uint32_t word,
                          const std::string& name) {
  const VkDeviceSize words = bytes / 4 * 4;  // every whole 32-bit word
  if (words == 0) return;
  run([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, dst, 0, words, word); },
      "staged fill (" + name + ")");
}

}  // namespace hrpp
