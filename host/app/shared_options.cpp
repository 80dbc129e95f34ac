#include "app/shared_options.h"

#include <map>

#include "app/cli_names.h"
#include "common/error.h"

namespace hrpp::app {

void add_shared_options(CLI::App* cmd, SharedOptions& o, SharedGroup group) {
  cmd->add_option("scene", o.scene,
                  "builtin:cornell, a .gltf/.glb file, a .scene.json manifest or the name of a "
                  "manifest in scenes/")
      ->capture_default_str();
  cmd->add_option("--bvh-bins", o.bvh.bin_count, "SAH bins per axis (2..64)")
      ->capture_default_str();
  cmd->add_option("--bvh-max-leaf", o.bvh.max_leaf_size, "Largest leaf, triangles (1..255)")
      ->capture_default_str();
  cmd->add_option("--bvh-intersection-cost", o.bvh.intersection_cost,
                  "SAH cost of a triangle test, in interior node visits (lower: larger leaves)")
      ->capture_default_str();
  cmd->add_option("--bvh-splits", o.bvh.splits,
                  "object: binned SAH object splits; spatial: also spatial splits (SBVH), at most "
                  "30% more references than triangles")
      ->transform(one_of(kBvhSplitsNames))
      ->default_str(name_in(kBvhSplitsNames, o.bvh.splits));
  if (group == SharedGroup::kScene) return;
  cmd->add_option_function<DeviceTracerKind>(
         "--tracer",
         [&o](const DeviceTracerKind& k) {
           o.device_tracer = k;
           o.vulkan.ray_query = k == DeviceTracerKind::kRayQuery;
         },
         "compute: the project's BVH kernels; rayquery: the driver's own traversal "
         "(VK_KHR_ray_query; lavapipe from Mesa 24.1, GPUs with ray tracing; bench: beside "
         "the BVH kernels)")
      ->transform(one_of(kDeviceTracerNames))
      ->default_str(name_in(kDeviceTracerNames, o.device_tracer));
  cmd->add_option("--bvh-nodes", o.nodes,
                  "binary: Aila-Laine 64-byte nodes (the reference; HRPP needs them); wide4: "
                  "4-wide 64-byte nodes, child boxes quantised to 8 bits; wide4-float: 4-wide "
                  "112-byte nodes, child boxes as floats (the wide ones: HRPP off only)")
      ->transform(one_of(kNodeFormatNames))
      ->default_str(node_format_name(o.nodes));
  cmd->add_option("--device", o.vulkan.device,
                  "Vulkan device: index or name substring (default: a GPU, else lavapipe)");
  cmd->add_option("--memory", o.vulkan.memory,
                  "Where buffers live: staged (device-local, copied through a staging buffer), "
                  "mapped (host-visible, mapped), auto (mapped on a CPU device or an integrated "
                  "GPU, else staged)")
      ->transform(one_of(kMemoryModeNames))
      ->default_str(name_in(kMemoryModeNames, o.vulkan.memory));
  cmd->add_flag("--validate,--vulkan-validate", o.vulkan.validate,
                "Vulkan validation layer on; any message fails the command");
  cmd->add_option("--rays-per-invocation", o.tracer.rays_per_invocation,
                  "Most rays one trace kernel invocation traces (default: 16 on a CPU device, "
                  "where lavapipe's loop limiter needs a bound; 1 on a GPU)")
      ->check(CLI::Range(1u, 1u << 24));
}

void check_compute_only(const SharedOptions& o,
                        std::initializer_list<std::pair<const char*, bool>> flags) {
  if (o.device_tracer != DeviceTracerKind::kRayQuery) return;
  const auto refuse = [](const char* flag) {
    throw Error(std::string(flag) +
                ": an option of the BVH kernels; --tracer rayquery traces the driver's own "
                "acceleration structure (use --tracer compute)");
  };
  if (o.nodes != NodeFormat::kBinary) refuse("--bvh-nodes");
  for (const auto& [flag, given] : flags)
    if (given) refuse(flag);
}

void check_validation_messages(const VulkanContext& ctx) {
  if (ctx.validation_messages() != 0)
    throw Error("Vulkan validation layer (--validate, --vulkan-validate or HRPP_VALIDATE=1): " +
                std::to_string(ctx.validation_messages()) + " messages (printed above)");
}

}  // namespace hrpp::app
