#include "front/gpu_ray_hash.h"

#include <algorithm>
#include <string>

#include "common/error.h"
#include "vk/compute_pipeline.h"
#include "vk/embedded_shaders.h"
#include "vk/storage_buffer.h"
#include "vk/vulkan_context.h"
#include "hrpp_interface.h"

namespace hrpp {

std::vector<std::uint64_t> hash_rays_on_gpu(VulkanContext& ctx, const gpu::HashParams& params,
                                            std::span<const gpu::Ray> rays) {
  if (!ctx.info().int64) throw Error(ctx.info().name + ": HRPP needs shaderInt64");
  std::vector<std::uint64_t> keys(rays.size());
  if (rays.empty()) return keys;
  const std::uint64_t groups =
      (rays.size() + HRPP_HASH_WORKGROUP_SIZE - 1) / HRPP_HASH_WORKGROUP_SIZE;
  if (groups > ctx.info().max_workgroup_count_x)
    throw Error("hrpp_hash_rays: " + std::to_string(rays.size()) + " rays is too many for one dispatch");
  StorageBuffer ray_buf(ctx, rays.size_bytes(), "ray array");
  StorageBuffer key_buf(ctx, keys.size() * sizeof(std::uint64_t), "key array");
  StorageBuffer param_buf(ctx, sizeof params, "hash parameters");
  ray_buf.upload(rays);
  key_buf.fill(0xFFFFFFFFu);  // poison: no key has bits above 47
  param_buf.upload(&params, sizeof params);
  ComputePipeline p(ctx, Kernel::hrpp_hash_rays, embedded_spirv(Kernel::hrpp_hash_rays),
                    HRPP_HASH_BINDING_COUNT, sizeof(std::uint32_t));
  p.bind(HRPP_HASH_BINDING_RAYS, ray_buf);
  p.bind(HRPP_HASH_BINDING_KEYS, key_buf);
  p.bind(HRPP_HASH_BINDING_PARAMS, param_buf);
  const auto count = static_cast<std::uint32_t>(rays.size());
  ctx.submit_and_wait(
      [&](VkCommandBuffer cmd) {
        record_dispatch(cmd, p, &count, static_cast<std::uint32_t>(groups), nullptr);
      },
      p.name());
  key_buf.download(std::span<std::uint64_t>(keys));
  if (std::any_of(keys.begin(), keys.end(), [](std::uint64_t k) { return k >> HRPP_KEY_BITS; }))
    throw Error("hrpp_hash_rays: keys left unwritten (or wider than 48 bits)");
  return keys;
}

}  // namespace hrpp
