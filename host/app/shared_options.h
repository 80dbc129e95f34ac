// The options that every subcommand loading a scene shares, defined once: the scene, the BVH
// build (--bvh-*), and for the commands that open the Vulkan device --tracer, --bvh-nodes,
// --device, --memory, --validate and --rays-per-invocation.
#pragma once

#include <initializer_list>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "gpu/device_tracer.h"
#include "gpu/gpu_tracer.h"
#include "vk/vulkan_context.h"

namespace hrpp::app {

struct SharedOptions {
  std::string scene = "builtin:cornell";
  BvhConfig bvh;
  NodeFormat nodes = NodeFormat::kBinary;  // --bvh-nodes (device commands)
  VulkanOptions vulkan;
  GpuTracerConfig tracer;  // rays_per_invocation (trace: also count_steps)
  // --tracer; kRayQuery also sets vulkan.ray_query.
  DeviceTracerKind device_tracer = DeviceTracerKind::kCompute;
};

enum class SharedGroup {
  kScene,   // scene and --bvh-* (hrpp scene)
  kDevice,  // those and the device's options (trace, bench, render)
};

// Registers the group on `cmd`. The validation layer's flag is --validate (also
// --vulkan-validate).
void add_shared_options(CLI::App* cmd, SharedOptions& o, SharedGroup group);

// With --tracer rayquery: throws the one-line error naming the first of `flags` (name, given)
// that only the compute tracer takes.
void check_compute_only(const SharedOptions& o,
                        std::initializer_list<std::pair<const char*, bool>> flags);

// Throws the one-line error of a run that printed Vulkan validation messages.
void check_validation_messages(const VulkanContext& ctx);

}  // namespace hrpp::app
