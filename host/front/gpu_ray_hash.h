// HRPP keys of a batch of rays computed on the GPU by the hrpp_hash_rays kernel: what the
// predictor kernels compute per ray, exposed so tests can hold it against the C++ mirror
// (host/hrpp/ray_hash.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "hrpp_types.h"

namespace hrpp {

class VulkanContext;

// One key per ray. Throws hrpp::Error when the device lacks 64-bit integers or a key comes back
// unwritten.
std::vector<std::uint64_t> hash_rays_on_gpu(VulkanContext& ctx, const gpu::HashParams& params,
                                            std::span<const gpu::Ray> rays);

}  // namespace hrpp
