// The kernels keep float subnormals where the device can promise it: Vulkan 1.2's float controls
// (VK_KHR_shader_float_controls, core in 1.2) let a shader declare the SPIR-V execution mode
// DenormPreserve for 32-bit floats when the device reports shaderDenormPreserveFloat32. Without
// it a device may flush subnormal inputs and results to zero (NVIDIA does; lavapipe keeps them
// but does not report the property), and C++'s answers on subnormal coordinates differ from the
// kernels' (docs/DEVICES.md, "Bit for bit on other devices").
// The kernels' SPIR-V is compiled without the mode; ComputePipeline adds it here, at load time,
// on a device that reports the property, because declaring it elsewhere is invalid.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace hrpp {

// `spirv` with OpCapability DenormPreserve and OpExecutionMode DenormPreserve 32 on each entry
// point (SPIR-V 1.4 or later: float controls need no OpExtension there). Throws hrpp::Error on a
// module that is not SPIR-V 1.4+ or has no entry point.
std::vector<std::uint32_t> with_denorm_preserve(std::span<const std::uint32_t> spirv);

}  // namespace hrpp
