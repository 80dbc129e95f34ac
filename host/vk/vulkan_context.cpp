#include "vk/vulkan_context.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>

#include <unistd.h>

#include "common/error.h"
#include "vk/staged_transfer.h"

namespace hrpp {

const char* vk_result_name(VkResult r) {
  switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_NOT_READY: return "VK_NOT_READY";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_INCOMPLETE: return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
    case VK_ERROR_UNKNOWN: return "VK_ERROR_UNKNOWN";
    default: return "VkResult error";
  }
}

void check_vk(VkResult r, const std::string& what) {
  if (r == VK_SUCCESS) return;
  if (r == VK_ERROR_DEVICE_LOST)
    throw DeviceFailure("Vulkan device lost during " + what +
                            " (VK_ERROR_DEVICE_LOST: driver crash or a kernel that ran too long)",
                        r);
  if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY)
    throw DeviceFailure(
        "out of device memory during " + what + " (VK_ERROR_OUT_OF_DEVICE_MEMORY)", r);
  if (r == VK_ERROR_OUT_OF_HOST_MEMORY)
    throw DeviceFailure("out of host memory during " + what + " (VK_ERROR_OUT_OF_HOST_MEMORY)", r);
  throw Error(what + " failed: " + vk_result_name(r));
}

const char* DeviceInfo::type_name() const {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

const char* DeviceInfo::denormals_text() const {
  return denorm_preserve ? "denormals kept"
                         : "denormals may flush (no shaderDenormPreserveFloat32)";
}

std::string DeviceInfo::summary() const {
  return name + " (" + type_name() + ", " + driver + ", subgroup " + std::to_string(subgroup_size) +
         ", " + denormals_text() + ")";
}

namespace {

// The Vulkan objects of a context, made in order by the constructor's steps below.
struct Handles {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t family = 0;
  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
};

// A test hook (docs/TESTING.md): HRPP_TEST_FAIL_SUBMIT=LABEL:N:lost|memory makes the N-th submit
// named LABEL (counting from 1) return VK_ERROR_DEVICE_LOST or VK_ERROR_OUT_OF_DEVICE_MEMORY in
// place of vkQueueSubmit's result, the command buffer not submitted: the failures a render
// cannot provoke on lavapipe. Throws hrpp::Error on a malformed value.
struct SubmitFailure {
  std::string label;
  std::uint64_t nth = 0;  // 0: no hook
  VkResult result = VK_SUCCESS;
  std::uint64_t seen = 0;

  static SubmitFailure from_env() {
    SubmitFailure f;
    const char* env = std::getenv("HRPP_TEST_FAIL_SUBMIT");
    if (env == nullptr || *env == '\0') return f;
    const std::string v = env;
    const std::size_t a = v.rfind(':'), b = a == std::string::npos ? a : v.rfind(':', a - 1);
    const std::string n = b == std::string::npos ? "" : v.substr(b + 1, a - b - 1);
    const std::string kind = a == std::string::npos ? "" : v.substr(a + 1);
    if (b == std::string::npos || b == 0 || n.empty() ||
        n.find_first_not_of("0123456789") != std::string::npos || (kind != "lost" && kind != "memory"))
      throw Error("HRPP_TEST_FAIL_SUBMIT=" + v + ": not LABEL:N:lost or LABEL:N:memory");
    f.label = v.substr(0, b);
    f.nth = std::stoull(n);
    f.result = kind == "lost" ? VK_ERROR_DEVICE_LOST : VK_ERROR_OUT_OF_DEVICE_MEMORY;
    return f;
  }
  // The result the submit named `what` is to get in place of the driver's; VK_SUCCESS: submit.
  VkResult next(const std::string& what) {
    if (nth == 0 || what != label || ++seen != nth) return VK_SUCCESS;
    return result;
  }
};

}  // namespace

struct VulkanContext::State {
  Handles h;
  DeviceInfo info;
  std::vector<DeviceInfo> devices;
  std::atomic<std::uint64_t> messages{0};
  MemoryLedger ledger;
  std::unique_ptr<StagedTransfer> staging;  // staged mode
  bool recording = false;                   // inside submit_and_wait's `record`
  bool ray_queries = false;                 // VulkanOptions::ray_query
  SubmitFailure injected;                   // HRPP_TEST_FAIL_SUBMIT

  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record, const std::string& what);

  ~State() {
    staging.reset();  // its buffer before the device
    if (h.device) {
      vkDeviceWaitIdle(h.device);
      if (h.fence) vkDestroyFence(h.device, h.fence, nullptr);
      if (h.pool) vkDestroyCommandPool(h.device, h.pool, nullptr);
      vkDestroyDevice(h.device, nullptr);
    }
    if (h.messenger) {
      auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(h.instance, "vkDestroyDebugUtilsMessengerEXT"));
      if (destroy) destroy(h.instance, h.messenger, nullptr);
    }
    if (h.instance) vkDestroyInstance(h.instance, nullptr);
  }
};

namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL on_debug_message(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT /*types*/,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* messages = static_cast<std::atomic<std::uint64_t>*>(user);
  messages->fetch_add(1);
  std::fprintf(stderr, "hrpp: vulkan %s: %s\n",
               (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ? "error" : "warning",
               data && data->pMessage ? data->pMessage : "(no message)");
  return VK_FALSE;
}

VkDebugUtilsMessengerCreateInfoEXT messenger_info(std::atomic<std::uint64_t>* counter) {
  VkDebugUtilsMessengerCreateInfoEXT ci{};
  ci.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
  ci.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  ci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                   VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                   VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  ci.pfnUserCallback = on_debug_message;
  ci.pUserData = counter;
  return ci;
}

bool has_layer(const char* name) {
  std::uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

// `layer`: an extension that layer provides (nullptr: the loader's and the drivers').
bool has_instance_extension(const char* name, const char* layer = nullptr) {
  std::uint32_t n = 0;
  vkEnumerateInstanceExtensionProperties(layer, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateInstanceExtensionProperties(layer, &n, exts.data());
  for (const auto& e : exts)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Why a device cannot run the kernels ("" when it can); fills the queue family.
std::string unsuitable(VkPhysicalDevice pd, const DeviceInfo& info, std::uint32_t* family) {
  if (VK_API_VERSION_MAJOR(info.api_version) == 1 && VK_API_VERSION_MINOR(info.api_version) < 2)
    return "needs Vulkan 1.2";
  std::uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
  int best = -1;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!(families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
    if (best < 0 || (families[best].timestampValidBits == 0 && families[i].timestampValidBits > 0))
      best = static_cast<int>(i);
  }
  if (best < 0) return "no compute queue";
  *family = static_cast<std::uint32_t>(best);
  if (!info.float64) return "no shaderFloat64";
  VkPhysicalDeviceSubgroupProperties sub{};
  sub.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
  VkPhysicalDeviceProperties2 p2{};
  p2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  p2.pNext = &sub;
  vkGetPhysicalDeviceProperties2(pd, &p2);
  const VkSubgroupFeatureFlags need = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_VOTE_BIT |
                                      VK_SUBGROUP_FEATURE_BALLOT_BIT |
                                      VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
  if (!(sub.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
      (sub.supportedOperations & need) != need)
    return "no subgroup vote/ballot/arithmetic in compute shaders";
  return "";
}

bool has_device_extension(VkPhysicalDevice pd, const char* name) {
  std::uint32_t n = 0;
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
  for (const auto& e : exts)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

// The buffer and memory limits of DeviceInfo (vk/memory_plan.h): maxMemoryAllocationSize
// (Vulkan 1.1), maxBufferSize (VK_KHR_maintenance4; no limit without it: the instance asks for
// Vulkan 1.2, so the 1.3 core query is not ours to make) and the heap of the memory type
// kDevice buffers take under the requested memory mode, or that heap's budget with
// VK_EXT_memory_budget.
void describe_memory(VkPhysicalDevice pd, MemoryMode requested, DeviceInfo* info) {
  VkPhysicalDeviceMaintenance4Properties m4{};
  m4.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_4_PROPERTIES;
  VkPhysicalDeviceMaintenance3Properties m3{};
  m3.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES;
  const bool has_m4 = has_device_extension(pd, VK_KHR_MAINTENANCE_4_EXTENSION_NAME);
  m3.pNext = has_m4 ? &m4 : nullptr;
  VkPhysicalDeviceProperties2 p2{};
  p2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  p2.pNext = &m3;
  vkGetPhysicalDeviceProperties2(pd, &p2);
  info->max_memory_allocation_size = m3.maxMemoryAllocationSize;
  info->max_buffer_size = has_m4 ? m4.maxBufferSize : ~std::uint64_t{0};

  VkPhysicalDeviceMemoryBudgetPropertiesEXT budget{};
  budget.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MEMORY_BUDGET_PROPERTIES_EXT;
  info->heap_budget = has_device_extension(pd, VK_EXT_MEMORY_BUDGET_EXTENSION_NAME);
  VkPhysicalDeviceMemoryProperties2 mp2{};
  mp2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MEMORY_PROPERTIES_2;
  mp2.pNext = info->heap_budget ? &budget : nullptr;
  vkGetPhysicalDeviceMemoryProperties2(pd, &mp2);
  const VkPhysicalDeviceMemoryProperties& mp = mp2.memoryProperties;
  info->memory_mode = resolve_memory_mode(requested, info->type);
  try {
    info->device_memory = choose_memory_type(mp, ~0u, info->memory_mode, MemoryRole::kDevice);
    info->host_shared_memory =
        choose_memory_type(mp, ~0u, info->memory_mode, MemoryRole::kHostShared);
  } catch (const Error&) {
    return;  // no host-visible memory: heap_bytes 0, every buffer refused by name
  }
  const std::uint32_t heap = info->device_memory.heap;
  info->heap_bytes = info->heap_budget ? budget.heapBudget[heap] : mp.memoryHeaps[heap].size;
  info->reported_heap_bytes = mp.memoryHeaps[heap].size;
  // A CPU device's buffers are the host's memory. Mesa 22.3's lavapipe reports a fixed 2 GiB
  // heap but allocates beyond it (5 GiB of buffers at once, measured), so the host's physical
  // memory is the real limit there (docs/DEVICES.md, "Device memory").
  if (!info->heap_budget && info->type == VK_PHYSICAL_DEVICE_TYPE_CPU) {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) {
      info->heap_bytes = static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
      info->heap_is_host = true;
    }
  }
}

// HRPP_DEVICE_HEAP_MIB=N caps the heap every check uses at N MiB (to leave room for other
// processes, or to try the limit). Throws hrpp::Error on a value that is not a number.
void apply_heap_cap(DeviceInfo* info) {
  const char* env = std::getenv("HRPP_DEVICE_HEAP_MIB");
  if (env == nullptr || *env == '\0') return;
  char* end = nullptr;
  const unsigned long long mib = std::strtoull(env, &end, 10);
  if (*end != '\0' || mib == 0)
    throw Error(std::string("HRPP_DEVICE_HEAP_MIB=") + env + ": not a positive whole number of MiB");
  info->heap_bytes = std::min<std::uint64_t>(info->heap_bytes, mib * 1024 * 1024);
  info->heap_capped = true;
}

// The extensions VulkanOptions::ray_query enables.
constexpr const char* kRayQueryExtensions[] = {VK_KHR_RAY_QUERY_EXTENSION_NAME,
                                               VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
                                               VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME};

// The device has the ray-query extensions, rayQuery, accelerationStructure and
// bufferDeviceAddress.
bool offers_ray_query(VkPhysicalDevice pd, const VkPhysicalDeviceVulkan12Features& f12) {
  for (const char* e : kRayQueryExtensions)
    if (!has_device_extension(pd, e)) return false;
  VkPhysicalDeviceRayQueryFeaturesKHR rq{};
  rq.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR;
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as{};
  as.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR;
  as.pNext = &rq;
  VkPhysicalDeviceFeatures2 f2{};
  f2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  f2.pNext = &as;
  vkGetPhysicalDeviceFeatures2(pd, &f2);
  return rq.rayQuery && as.accelerationStructure && f12.bufferDeviceAddress;
}

DeviceInfo describe(VkPhysicalDevice pd, std::uint32_t index, MemoryMode memory) {
  VkPhysicalDeviceSubgroupProperties sub{};
  sub.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
  VkPhysicalDeviceFloatControlsProperties floats{};
  floats.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FLOAT_CONTROLS_PROPERTIES;
  floats.pNext = &sub;
  VkPhysicalDeviceDriverProperties driver{};
  driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
  driver.pNext = &floats;
  VkPhysicalDeviceProperties2 p2{};
  p2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  p2.pNext = &driver;
  vkGetPhysicalDeviceProperties2(pd, &p2);
  VkPhysicalDeviceVulkan12Features f12{};
  f12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
  VkPhysicalDeviceFeatures2 f2{};
  f2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  f2.pNext = &f12;
  vkGetPhysicalDeviceFeatures2(pd, &f2);

  const VkPhysicalDeviceProperties& p = p2.properties;
  DeviceInfo info;
  info.name = p.deviceName;
  info.index = index;
  info.type = p.deviceType;
  info.api_version = p.apiVersion;
  info.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  info.subgroup_size = sub.subgroupSize;
  info.float64 = f2.features.shaderFloat64;
  info.int64 = f2.features.shaderInt64;
  info.int64_atomics = f12.shaderBufferInt64Atomics;
  info.denorm_preserve = floats.shaderDenormPreserveFloat32;
  info.max_storage_buffer_range = p.limits.maxStorageBufferRange;
  info.max_texel_buffer_elements = p.limits.maxTexelBufferElements;
  info.max_workgroup_count_x = p.limits.maxComputeWorkGroupCount[0];
  info.timestamp_period_ns = p.limits.timestampPeriod;
  info.ray_query = offers_ray_query(pd, f12);
  describe_memory(pd, memory, &info);
  return info;
}

std::uint32_t timestamp_bits(VkPhysicalDevice pd, std::uint32_t family) {
  std::uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
  return family < n ? families[family].timestampValidBits : 0;
}

int type_rank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 4;
    default: return 3;
  }
}

std::string device_list(const std::vector<DeviceInfo>& devices) {
  std::string s;
  for (const DeviceInfo& d : devices)
    s += (s.empty() ? "" : ", ") + std::to_string(d.index) + " '" + d.name + "'";
  return s;
}

}  // namespace

namespace {

MemoryTypeReport type_report(const MemoryTypeChoice& c) {
  return {c.type, c.heap, memory_flags_text(c.flags), c.mapped};
}

MemoryPlacement placement_report(const DeviceInfo& info) {
  return {
      name_in(kMemoryModeNames, info.memory_mode),
      {{name_in(kMemoryRoleNames, MemoryRole::kDevice), type_report(info.device_memory)},
       {name_in(kMemoryRoleNames, MemoryRole::kHostShared), type_report(info.host_shared_memory)}}};
}

constexpr const char* kInstall =
    "install a Vulkan driver (Debian: apt-get install mesa-vulkan-drivers, for lavapipe)";

// The instance, with VK_LAYER_KHRONOS_validation and a messenger counting into `messages` when
// `validate`.
void create_instance(Handles& h, bool validate,
                     std::atomic<std::uint64_t>* messages) {
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "hrpp";
  app.applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
  app.pEngineName = "hrpp";
  app.apiVersion = VK_API_VERSION_1_2;
  std::vector<const char*> layers, extensions;
  VkDebugUtilsMessengerCreateInfoEXT dbg = messenger_info(messages);
  // Synchronization validation beside the layer's default checks: missing or wrong barriers
  // (the staged copies', the kernels') are reported like any other message.
  const VkValidationFeatureEnableEXT sync =
      VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features{};
  features.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT;
  features.pNext = &dbg;
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &sync;
  VkInstanceCreateInfo ici{};
  ici.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  ici.pApplicationInfo = &app;
  if (validate) {
    if (!has_layer("VK_LAYER_KHRONOS_validation"))
      throw Error("--validate: the Vulkan layer VK_LAYER_KHRONOS_validation is not installed "
                  "(Debian: apt-get install vulkan-validationlayers)");
    if (!has_instance_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME))
      throw Error("--validate: the Vulkan loader lacks " VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    layers.push_back("VK_LAYER_KHRONOS_validation");
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    ici.pNext = &dbg;  // also reports on vkCreateInstance / vkDestroyInstance
    if (has_instance_extension(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME,
                               "VK_LAYER_KHRONOS_validation")) {
      extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
      ici.pNext = &features;
    }
  }
  ici.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
  ici.ppEnabledLayerNames = layers.data();
  ici.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
  ici.ppEnabledExtensionNames = extensions.data();
  const VkResult ir = vkCreateInstance(&ici, nullptr, &h.instance);
  if (ir == VK_ERROR_INCOMPATIBLE_DRIVER || ir == VK_ERROR_INITIALIZATION_FAILED)
    throw Error(std::string("no usable Vulkan driver (vkCreateInstance: ") + vk_result_name(ir) +
                "); " + kInstall);
  check_vk(ir, "vkCreateInstance");
  if (!validate) return;
  auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(h.instance, "vkCreateDebugUtilsMessengerEXT"));
  if (!create) throw Error("--validate: vkCreateDebugUtilsMessengerEXT is missing");
  check_vk(create(h.instance, &dbg, nullptr, &h.messenger), "vkCreateDebugUtilsMessengerEXT");
}

// Every device of the instance, in Vulkan's order.
std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  std::uint32_t count = 0;
  const VkResult er = vkEnumeratePhysicalDevices(instance, &count, nullptr);
  if (er != VK_SUCCESS || count == 0)
    throw Error(std::string("no Vulkan device found (vkEnumeratePhysicalDevices: ") +
                vk_result_name(er) + ", " + std::to_string(count) + " devices); " + kInstall);
  std::vector<VkPhysicalDevice> physical(count);
  check_vk(vkEnumeratePhysicalDevices(instance, &count, physical.data()),
           "vkEnumeratePhysicalDevices");
  physical.resize(count);
  return physical;
}

// The index of the device --device names (see VulkanOptions::device) that can run the kernels,
// real GPUs first; fills its compute queue family.
std::uint32_t choose_device(const std::vector<VkPhysicalDevice>& physical,
                            const std::vector<DeviceInfo>& devices, const std::string& want,
                            std::uint32_t* family) {
  const bool by_index = !want.empty() && std::all_of(want.begin(), want.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c));
  });
  std::vector<std::uint32_t> candidates;
  for (std::uint32_t i = 0; i < devices.size(); ++i)
    if (by_index ? want == std::to_string(i)
                 : lower(devices[i].name).find(lower(want)) != std::string::npos)
      candidates.push_back(i);
  if (candidates.empty())
    throw Error("--device " + want + ": no such Vulkan device (found: " + device_list(devices) +
                ")");
  std::stable_sort(candidates.begin(), candidates.end(), [&](std::uint32_t a, std::uint32_t b) {
    return type_rank(devices[a].type) < type_rank(devices[b].type);
  });
  std::string why;
  for (std::uint32_t i : candidates) {
    const std::string reason = unsuitable(physical[i], devices[i], family);
    if (reason.empty()) return i;
    why += (why.empty() ? "" : "; ") + devices[i].name + ": " + reason;
  }
  throw Error("no Vulkan device can run the compute kernels (" + why + "); " + kInstall);
}

// The logical device with float64 (watertight fallback), int64 and int64 atomics when offered,
// ray queries when `ray_query` (the caller has checked info.ray_query), and its one compute
// queue.
void create_device(Handles& h, const DeviceInfo& info, bool ray_query) {
  VkPhysicalDeviceRayQueryFeaturesKHR rq{};
  rq.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR;
  rq.rayQuery = VK_TRUE;
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as{};
  as.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR;
  as.pNext = &rq;
  as.accelerationStructure = VK_TRUE;
  VkPhysicalDeviceVulkan12Features f12{};
  f12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
  f12.pNext = ray_query ? &as : nullptr;
  f12.shaderBufferInt64Atomics = info.int64_atomics;
  f12.bufferDeviceAddress = ray_query;
  VkPhysicalDeviceFeatures2 f2{};
  f2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  f2.pNext = &f12;
  f2.features.shaderFloat64 = VK_TRUE;
  f2.features.shaderInt64 = info.int64;
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{};
  qci.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  qci.queueFamilyIndex = h.family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  VkDeviceCreateInfo dci{};
  dci.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  dci.pNext = &f2;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  if (ray_query) {
    dci.enabledExtensionCount = static_cast<std::uint32_t>(std::size(kRayQueryExtensions));
    dci.ppEnabledExtensionNames = kRayQueryExtensions;
  }
  check_vk(vkCreateDevice(h.physical, &dci, nullptr, &h.device), "vkCreateDevice");
  vkGetDeviceQueue(h.device, h.family, 0, &h.queue);
}

// The command pool, the one reusable command buffer and the fence of submit_and_wait.
void create_command_objects(Handles& h) {
  VkCommandPoolCreateInfo pci{};
  pci.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pci.queueFamilyIndex = h.family;
  check_vk(vkCreateCommandPool(h.device, &pci, nullptr, &h.pool), "vkCreateCommandPool");
  VkCommandBufferAllocateInfo cai{};
  cai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  cai.commandPool = h.pool;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = 1;
  check_vk(vkAllocateCommandBuffers(h.device, &cai, &h.cmd), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fci{};
  fci.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  check_vk(vkCreateFence(h.device, &fci, nullptr, &h.fence), "vkCreateFence");
}

}  // namespace

VulkanContext::VulkanContext(const VulkanOptions& options) : s_(std::make_unique<State>()) {
  // HRPP_VALIDATE=1 turns validation on for every context of the process (CI's GPU tests, and
  // the hrpp commands they run, whose --validate check then fails on any message).
  const char* env = std::getenv("HRPP_VALIDATE");
  const bool validate = options.validate || (env != nullptr && std::string(env) == "1");
  State& s = *s_;
  create_instance(s.h, validate, &s.messages);
  const std::vector<VkPhysicalDevice> physical = physical_devices(s.h.instance);
  for (std::uint32_t i = 0; i < physical.size(); ++i)
    s.devices.push_back(describe(physical[i], i, options.memory));
  const std::uint32_t chosen = choose_device(physical, s.devices, options.device, &s.h.family);
  s.h.physical = physical[chosen];
  s.info = s.devices[chosen];
  s.info.timestamps = timestamp_bits(s.h.physical, s.h.family) > 0;
  apply_heap_cap(&s.info);
  s.injected = SubmitFailure::from_env();
  s.ledger.set_heap(s.info.heap_bytes);
  if (options.ray_query && !s.info.ray_query)
    throw Error("--tracer rayquery: the Vulkan device '" + s.info.name + "' (" + s.info.driver +
                ") has no VK_KHR_ray_query with VK_KHR_acceleration_structure (lavapipe has "
                "them from Mesa 24.1; GPUs with ray tracing do)");
  s.ray_queries = options.ray_query;
  create_device(s.h, s.info, options.ray_query);
  create_command_objects(s.h);
  s.ledger.set_placement(placement_report(s.info));
  if (s.info.memory_mode == MemoryMode::kStaged)
    s.staging = std::make_unique<StagedTransfer>(
        *this, [&s](const std::function<void(VkCommandBuffer)>& record, const std::string& what) {
          s.submit_and_wait(record, what);
        });
}

VulkanContext::~VulkanContext() = default;
VulkanContext::VulkanContext(VulkanContext&&) noexcept = default;
VulkanContext& VulkanContext::operator=(VulkanContext&&) noexcept = default;

const DeviceInfo& VulkanContext::info() const { return s_->info; }
const std::vector<DeviceInfo>& VulkanContext::devices() const { return s_->devices; }
std::uint64_t VulkanContext::validation_messages() const { return s_->messages.load(); }
MemoryLedger& VulkanContext::memory() { return s_->ledger; }
const MemoryLedger& VulkanContext::memory() const { return s_->ledger; }
StagedTransfer* VulkanContext::staging() { return s_->staging.get(); }
bool VulkanContext::ray_queries() const { return s_->ray_queries; }
VkDevice VulkanContext::device() const { return s_->h.device; }
VkPhysicalDevice VulkanContext::physical_device() const { return s_->h.physical; }
std::uint32_t VulkanContext::queue_family() const { return s_->h.family; }

void VulkanContext::submit_and_wait(const std::function<void(VkCommandBuffer)>& record,
                                    const std::string& what) {
  s_->submit_and_wait(record, what);
}

void VulkanContext::State::submit_and_wait(const std::function<void(VkCommandBuffer)>& record,
                                           const std::string& what) {
  if (recording)
    throw Error(what +
                ": submitted while another command buffer is being recorded (a staged "
                "buffer's upload, download or fill inside a recording)");
  Handles& s = h;
  check_vk(vkResetCommandBuffer(s.cmd, 0), "vkResetCommandBuffer (" + what + ")");
  VkCommandBufferBeginInfo bi{};
  bi.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check_vk(vkBeginCommandBuffer(s.cmd, &bi), "vkBeginCommandBuffer (" + what + ")");
  recording = true;
  try {
    record(s.cmd);
  } catch (...) {
    recording = false;
    throw;
  }
  recording = false;
  // Shader writes → host reads of the mapped buffers once the fence has signalled.
  VkMemoryBarrier to_host{};
  to_host.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  to_host.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(s.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0, nullptr, 0, nullptr);
  check_vk(vkEndCommandBuffer(s.cmd), "vkEndCommandBuffer (" + what + ")");
  check_vk(vkResetFences(s.device, 1, &s.fence), "vkResetFences (" + what + ")");
  VkSubmitInfo si{};
  si.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  si.commandBufferCount = 1;
  si.pCommandBuffers = &s.cmd;
  const VkResult forced = injected.next(what);
  check_vk(forced != VK_SUCCESS ? forced : vkQueueSubmit(s.queue, 1, &si, s.fence),
           "vkQueueSubmit (" + what + ")");
  check_vk(vkWaitForFences(s.device, 1, &s.fence, VK_TRUE, UINT64_MAX),
           "vkWaitForFences (" + what + ")");
}

}  // namespace hrpp
