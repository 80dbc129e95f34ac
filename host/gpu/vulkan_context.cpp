#include "gpu/vulkan_context.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "common/error.h"

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
    throw Error("Vulkan device lost during " + what +
                " (driver crash or a kernel that ran too long); results are unusable");
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

struct VulkanContext::State {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t family = 0;
  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  DeviceInfo info;
  std::vector<DeviceInfo> devices;
  std::atomic<std::uint64_t> messages{0};

  ~State() {
    if (device) {
      vkDeviceWaitIdle(device);
      if (fence) vkDestroyFence(device, fence, nullptr);
      if (pool) vkDestroyCommandPool(device, pool, nullptr);
      vkDestroyDevice(device, nullptr);
    }
    if (messenger) {
      auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
      if (destroy) destroy(instance, messenger, nullptr);
    }
    if (instance) vkDestroyInstance(instance, nullptr);
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

bool has_instance_extension(const char* name) {
  std::uint32_t n = 0;
  vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateInstanceExtensionProperties(nullptr, &n, exts.data());
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

DeviceInfo describe(VkPhysicalDevice pd, std::uint32_t index) {
  VkPhysicalDeviceSubgroupProperties sub{};
  sub.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
  VkPhysicalDeviceDriverProperties driver{};
  driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
  driver.pNext = &sub;
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
  info.max_storage_buffer_range = p.limits.maxStorageBufferRange;
  info.max_texel_buffer_elements = p.limits.maxTexelBufferElements;
  info.max_workgroup_count_x = p.limits.maxComputeWorkGroupCount[0];
  info.timestamp_period_ns = p.limits.timestampPeriod;
  return info;
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

VulkanContext::VulkanContext(const VulkanOptions& options) : s_(std::make_unique<State>()) {
  // HRPP_VALIDATE=1 turns validation on for every context of the process (CI's GPU tests, and
  // the hrpp commands they run, whose --validate check then fails on any message).
  const char* env = std::getenv("HRPP_VALIDATE");
  const bool validate = options.validate || (env != nullptr && std::string(env) == "1");
  State& s = *s_;
  constexpr const char* kInstall =
      "install a Vulkan driver (Debian: apt-get install mesa-vulkan-drivers, for lavapipe)";

  // Instance (+ validation).
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "hrpp";
  app.applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
  app.pEngineName = "hrpp";
  app.apiVersion = VK_API_VERSION_1_2;
  std::vector<const char*> layers, extensions;
  VkDebugUtilsMessengerCreateInfoEXT dbg = messenger_info(&s.messages);
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
  }
  ici.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
  ici.ppEnabledLayerNames = layers.data();
  ici.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
  ici.ppEnabledExtensionNames = extensions.data();
  const VkResult ir = vkCreateInstance(&ici, nullptr, &s.instance);
  if (ir == VK_ERROR_INCOMPATIBLE_DRIVER || ir == VK_ERROR_INITIALIZATION_FAILED)
    throw Error(std::string("no usable Vulkan driver (vkCreateInstance: ") + vk_result_name(ir) +
                "); " + kInstall);
  check_vk(ir, "vkCreateInstance");
  if (validate) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(s.instance, "vkCreateDebugUtilsMessengerEXT"));
    if (!create) throw Error("--validate: vkCreateDebugUtilsMessengerEXT is missing");
    check_vk(create(s.instance, &dbg, nullptr, &s.messenger), "vkCreateDebugUtilsMessengerEXT");
  }

  // Devices.
  std::uint32_t count = 0;
  const VkResult er = vkEnumeratePhysicalDevices(s.instance, &count, nullptr);
  if (er != VK_SUCCESS || count == 0)
    throw Error(std::string("no Vulkan device found (vkEnumeratePhysicalDevices: ") +
                vk_result_name(er) + ", " + std::to_string(count) + " devices); " + kInstall);
  std::vector<VkPhysicalDevice> physical(count);
  check_vk(vkEnumeratePhysicalDevices(s.instance, &count, physical.data()),
           "vkEnumeratePhysicalDevices");
  physical.resize(count);
  for (std::uint32_t i = 0; i < count; ++i) s.devices.push_back(describe(physical[i], i));

  std::vector<std::uint32_t> candidates;
  const std::string& want = options.device;
  const bool by_index =
      !want.empty() && std::all_of(want.begin(), want.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
  for (std::uint32_t i = 0; i < count; ++i) {
    if (by_index ? want == std::to_string(i)
                 : lower(s.devices[i].name).find(lower(want)) != std::string::npos)
      candidates.push_back(i);
  }
  if (candidates.empty())
    throw Error("--device " + want + ": no such Vulkan device (found: " + device_list(s.devices) +
                ")");
  std::stable_sort(candidates.begin(), candidates.end(), [&](std::uint32_t a, std::uint32_t b) {
    return type_rank(s.devices[a].type) < type_rank(s.devices[b].type);
  });
  std::string why;
  int chosen = -1;
  for (std::uint32_t i : candidates) {
    const std::string reason = unsuitable(physical[i], s.devices[i], &s.family);
    if (reason.empty()) {
      chosen = static_cast<int>(i);
      break;
    }
    why += (why.empty() ? "" : "; ") + s.devices[i].name + ": " + reason;
  }
  if (chosen < 0)
    throw Error("no Vulkan device can run the compute kernels (" + why + "); " + kInstall);
  s.physical = physical[chosen];
  s.info = s.devices[chosen];

  std::uint32_t nf = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(s.physical, &nf, nullptr);
  std::vector<VkQueueFamilyProperties> families(nf);
  vkGetPhysicalDeviceQueueFamilyProperties(s.physical, &nf, families.data());
  s.info.timestamps = families[s.family].timestampValidBits > 0;

  // Logical device: float64 (watertight fallback), int64 and int64 atomics when offered.
  VkPhysicalDeviceVulkan12Features f12{};
  f12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
  f12.shaderBufferInt64Atomics = s.info.int64_atomics;
  VkPhysicalDeviceFeatures2 f2{};
  f2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  f2.pNext = &f12;
  f2.features.shaderFloat64 = VK_TRUE;
  f2.features.shaderInt64 = s.info.int64;
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{};
  qci.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  qci.queueFamilyIndex = s.family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  VkDeviceCreateInfo dci{};
  dci.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  dci.pNext = &f2;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  check_vk(vkCreateDevice(s.physical, &dci, nullptr, &s.device), "vkCreateDevice");
  vkGetDeviceQueue(s.device, s.family, 0, &s.queue);

  VkCommandPoolCreateInfo pci{};
  pci.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pci.queueFamilyIndex = s.family;
  check_vk(vkCreateCommandPool(s.device, &pci, nullptr, &s.pool), "vkCreateCommandPool");
  VkCommandBufferAllocateInfo cai{};
  cai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  cai.commandPool = s.pool;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = 1;
  check_vk(vkAllocateCommandBuffers(s.device, &cai, &s.cmd), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fci{};
  fci.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  check_vk(vkCreateFence(s.device, &fci, nullptr, &s.fence), "vkCreateFence");
}

VulkanContext::~VulkanContext() = default;
VulkanContext::VulkanContext(VulkanContext&&) noexcept = default;
VulkanContext& VulkanContext::operator=(VulkanContext&&) noexcept = default;

const DeviceInfo& VulkanContext::info() const { return s_->info; }
const std::vector<DeviceInfo>& VulkanContext::devices() const { return s_->devices; }
std::uint64_t VulkanContext::validation_messages() const { return s_->messages.load(); }
VkDevice VulkanContext::device() const { return s_->device; }
VkPhysicalDevice VulkanContext::physical_device() const { return s_->physical; }
std::uint32_t VulkanContext::queue_family() const { return s_->family; }

void VulkanContext::submit_and_wait(const std::function<void(VkCommandBuffer)>& record,
                                    const std::string& what) {
  State& s = *s_;
  check_vk(vkResetCommandBuffer(s.cmd, 0), "vkResetCommandBuffer (" + what + ")");
  VkCommandBufferBeginInfo bi{};
  bi.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check_vk(vkBeginCommandBuffer(s.cmd, &bi), "vkBeginCommandBuffer (" + what + ")");
  record(s.cmd);
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
  check_vk(vkQueueSubmit(s.queue, 1, &si, s.fence), what);
  check_vk(vkWaitForFences(s.device, 1, &s.fence, VK_TRUE, UINT64_MAX), what);
}

}  // namespace hrpp
