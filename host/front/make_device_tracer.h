// The device tracer a command asks for: the one place that names the backends (--tracer
// compute or rayquery) and puts HRPP's stage in front of them (front/predicting_tracer.h) when
// the predictor is enabled.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "bvh/gpu_layout.h"
#include "gpu/device_tracer.h"
#include "gpu/device_tracer_kind.h"
#include "gpu/gpu_tracer_config.h"
#include "hrpp/predictor_config.h"
#include "vk/memory_plan.h"

namespace hrpp {

class VulkanContext;

// The buffers the tracer of `kind` over `bvh` allocates with `resident_rays` rays of each
// query kind resident, HRPP's stage and (in front of the driver's ray queries) the BVH it
// verifies on included; the driver's structures are not known before their build. For
// check_fits (vk/memory_plan.h).
std::vector<BufferNeed> device_tracer_needs(DeviceTracerKind kind, const GpuBvh& bvh,
                                            const PredictorConfig& predictor,
                                            std::size_t resident_rays);

// Most rays one trace dispatch of `kind` reaches on `device` with `config`.
std::size_t device_tracer_dispatch_rays(DeviceTracerKind kind, const DeviceInfo& device,
                                        const GpuTracerConfig& config);

// The tracer of `kind`, with `predictor.enabled` behind a PredictingTracer. The BVH kernels'
// tracer checks its buffers and the stage's against the device first (check_fits) and, with
// `release` (the same GpuBvh as `bvh`), frees each host array once the device holds it; in
// serial mode (PredictorConfig::serial) its kernels take one ray per subgroup, as the stage's.
std::unique_ptr<DeviceTracer> make_device_tracer(VulkanContext& ctx, DeviceTracerKind kind,
                                                 const GpuBvh& bvh, const GpuTracerConfig& tracer,
                                                 const PredictorConfig& predictor,
                                                 GpuBvh* release = nullptr);

}  // namespace hrpp
