// The Vulkan instance, the chosen compute device and its queue: the root of host/gpu/, the only
// stage that creates and destroys Vulkan objects. Move-only; everything else borrows it.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "common/error.h"

#include "vk/memory_ledger.h"
#include "vk/memory_placement.h"

namespace hrpp {

struct VulkanOptions {
  // "" picks a real GPU when there is one, else a CPU driver (lavapipe). Digits: the index in
  // Vulkan's enumeration order; anything else: a case-insensitive substring of the device name.
  std::string device;
  // VK_LAYER_KHRONOS_validation with a debug-utils messenger that prints every warning and error
  // to stderr and counts them (validation_messages()). Also on when the environment has
  // HRPP_VALIDATE=1 (CI runs every GPU test so, and the commands treat any message as an error).
  // Synchronization validation is on with it.
  bool validate = false;
  // --memory: where buffers live (vk/memory_placement.h); kAuto is resolved by the device's type.
  MemoryMode memory = MemoryMode::kAuto;
  // --tracer rayquery: enable the driver's ray tracing (VK_KHR_ray_query with
  // VK_KHR_acceleration_structure, and buffer device addresses); the context refuses a device
  // without it (DeviceInfo::ray_query).
  bool ray_query = false;
};

class StagedTransfer;

// What the kernels and the reports need to know about the chosen device.
struct DeviceInfo {
  std::string name;
  std::uint32_t index = 0;  // in vkEnumeratePhysicalDevices order
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  std::uint32_t api_version = 0;
  std::string driver;               // driver name and info, e.g. "llvmpipe Mesa 22.3.6"
  std::uint32_t subgroup_size = 0;  // never assumed by the kernels; HRPP serial mode sizes by it
  bool float64 = false;             // shaderFloat64 (required: watertight double fallback)
  bool int64 = false;               // shaderInt64
  bool int64_atomics = false;       // shaderBufferInt64Atomics
  // shaderDenormPreserveFloat32: the kernels keep float subnormals (vk/float_controls.h);
  // false: the device may flush them, and C++'s answers on subnormals may differ.
  bool denorm_preserve = false;
  std::uint64_t max_storage_buffer_range = 0;  // bytes one storage-buffer binding may span
  std::uint32_t max_texel_buffer_elements = 0;  // texels one texel-buffer view may span
  std::uint64_t max_memory_allocation_size = 0;  // bytes of one allocation (one buffer here)
  std::uint64_t max_buffer_size = 0;             // bytes of one VkBuffer
  // The memory mode, resolved (never kAuto), and the memory type of each role under it
  // (choose_memory_type with every type allowed: StorageBuffer's buffers all allow the same).
  MemoryMode memory_mode = MemoryMode::kMapped;
  MemoryTypeChoice device_memory;       // MemoryRole::kDevice
  MemoryTypeChoice host_shared_memory;  // MemoryRole::kHostShared
  // What all of a scene's buffers together must fit (vk/memory_plan.h): the heap of the memory
  // type kDevice buffers use (device_memory), or its budget where the device has
  // VK_EXT_memory_budget, or on a CPU device the host's physical memory; at most
  // HRPP_DEVICE_HEAP_MIB when that is set.
  std::uint64_t heap_bytes = 0;
  std::uint64_t reported_heap_bytes = 0;  // the heap's size as the device reports it
  bool heap_budget = false;               // heap_bytes is VK_EXT_memory_budget's budget
  bool heap_is_host = false;              // heap_bytes is the host's memory (a CPU device)
  bool heap_capped = false;               // HRPP_DEVICE_HEAP_MIB applied
  std::uint32_t max_workgroup_count_x = 0;
  double timestamp_period_ns = 0.0;  // ns per timestamp tick
  bool timestamps = false;           // the compute queue writes timestamps
  // The device offers VK_KHR_ray_query and VK_KHR_acceleration_structure (with
  // VK_KHR_deferred_host_operations) and their features: the driver's own BVH traversal.
  bool ray_query = false;

  const char* type_name() const;
  // What the device promises about float subnormals.
  const char* denormals_text() const;
  // The device line: "NAME (TYPE, DRIVER, subgroup N, DENORMALS)".
  std::string summary() const;
};

class VulkanContext {
 public:
  // Throws hrpp::Error with one line when there is no Vulkan driver, no device with compute
  // (Vulkan 1.2, shaderFloat64, subgroup vote/ballot/arithmetic), no device matching
  // options.device, or (options.ray_query) a chosen device without ray queries.
  explicit VulkanContext(const VulkanOptions& options = {});
  ~VulkanContext();
  VulkanContext(VulkanContext&&) noexcept;
  VulkanContext& operator=(VulkanContext&&) noexcept;
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  const DeviceInfo& info() const;
  // Every device Vulkan lists, capable or not (for messages and `--device` help).
  const std::vector<DeviceInfo>& devices() const;
  // Validation warnings and errors seen so far (0 when validation is off).
  std::uint64_t validation_messages() const;

  // Records commands into a fresh primary command buffer, submits it on the compute queue and
  // waits on a fence. `what` names the work in errors (device lost). Throws hrpp::Error when
  // called from inside `record` (a staged buffer's upload while recording, say).
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record, const std::string& what);

  // The buffers allocated now, by name (StorageBuffer keeps it), and their peak.
  MemoryLedger& memory();
  const MemoryLedger& memory() const;
  // The staging copies of kDevice buffers in staged mode; nullptr in mapped mode.
  StagedTransfer* staging();
  // Ray queries are enabled (VulkanOptions::ray_query): every StorageBuffer then has a device
  // address and may hold or feed an acceleration structure.
  bool ray_queries() const;

  VkDevice device() const;
  VkPhysicalDevice physical_device() const;
  std::uint32_t queue_family() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// A failure of the device itself, not of the input: the device lost, or out of device or host
// memory. A render that meets one mid-way keeps the passes it had finished (render/).
class DeviceFailure : public Error {
 public:
  DeviceFailure(const std::string& message, VkResult result) : Error(message), result_(result) {}
  VkResult result() const { return result_; }

 private:
  VkResult result_;
};

// Throws hrpp::Error("<what> failed: <VkResult name>") when r is not VK_SUCCESS; a lost device
// and running out of device or host memory throw a DeviceFailure with their own one-line
// messages naming `what`.
void check_vk(VkResult r, const std::string& what);

const char* vk_result_name(VkResult r);

}  // namespace hrpp
