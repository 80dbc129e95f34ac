#include "vk/acceleration_structure.h"

#include <algorithm>
#include <chrono>
#include <string>
#include <utility>

#include "common/error.h"
#include "vk/storage_buffer.h"
#include "vk/vulkan_context.h"

namespace hrpp {
namespace {

// The extension's commands: the loader exports core commands only.
struct Commands {
  PFN_vkCreateAccelerationStructureKHR create = nullptr;
  PFN_vkDestroyAccelerationStructureKHR destroy = nullptr;
  PFN_vkGetAccelerationStructureBuildSizesKHR build_sizes = nullptr;
  PFN_vkCmdBuildAccelerationStructuresKHR build = nullptr;
  PFN_vkGetAccelerationStructureDeviceAddressKHR address = nullptr;
  PFN_vkCmdWriteAccelerationStructuresPropertiesKHR write_properties = nullptr;
  PFN_vkCmdCopyAccelerationStructureKHR copy = nullptr;

  explicit Commands(VkDevice d) {
    load(d, create, "vkCreateAccelerationStructureKHR");
    load(d, destroy, "vkDestroyAccelerationStructureKHR");
    load(d, build_sizes, "vkGetAccelerationStructureBuildSizesKHR");
    load(d, build, "vkCmdBuildAccelerationStructuresKHR");
    load(d, address, "vkGetAccelerationStructureDeviceAddressKHR");
    load(d, write_properties, "vkCmdWriteAccelerationStructuresPropertiesKHR");
    load(d, copy, "vkCmdCopyAccelerationStructureKHR");
  }

  template <class F>
  static void load(VkDevice d, F& f, const char* name) {
    f = reinterpret_cast<F>(vkGetDeviceProcAddr(d, name));
    if (!f) throw Error(std::string("the Vulkan driver lacks ") + name);
  }
};

// Everything the builds before `next` wrote (transfers, builds, copies) is visible to `next`'s
// stages: the inputs' uploads, the bottom level under the top, the top level under the kernels.
void build_barrier(VkCommandBuffer cmd, VkPipelineStageFlags next, VkAccessFlags read) {
  VkMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
  b.dstAccessMask = read;
  vkCmdPipelineBarrier(cmd,
                       VK_PIPELINE_STAGE_TRANSFER_BIT |
                           VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                       next, 0, 1, &b, 0, nullptr, 0, nullptr);
}

constexpr VkPipelineStageFlags kBuildStage = VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR;
constexpr VkAccessFlags kBuildReads =
    VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR | VK_ACCESS_SHADER_READ_BIT;

// One acceleration structure and the buffer that holds it; the structure is destroyed before
// its buffer. Move-only.
struct Level {
  StorageBuffer storage;
  VkAccelerationStructureKHR handle = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  PFN_vkDestroyAccelerationStructureKHR destroy = nullptr;

  Level() = default;
  Level(Level&& o) noexcept
      : storage(std::move(o.storage)),
        handle(std::exchange(o.handle, VK_NULL_HANDLE)),
        device(o.device),
        destroy(o.destroy) {}
  Level& operator=(Level&& o) noexcept {
    if (this != &o) {
      release();
      storage = std::move(o.storage);
      handle = std::exchange(o.handle, VK_NULL_HANDLE);
      device = o.device;
      destroy = o.destroy;
    }
    return *this;
  }
  ~Level() { release(); }
  void release() noexcept {
    if (handle) destroy(device, handle, nullptr);
    handle = VK_NULL_HANDLE;
  }
};

}  // namespace

struct AccelerationStructure::State {
  VulkanContext* ctx;
  Commands vk;
  Level bottom, top;
  AccelerationStructureStats stats;

  State(VulkanContext& c, std::span<const glm::vec3> vertices) : ctx(&c), vk(c.device()) {
    if (!c.ray_queries()) throw Error("acceleration structures need a context with ray queries");
    const auto start = std::chrono::steady_clock::now();
    build_bottom(vertices);
    build_top();
    stats.build_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count();
  }

  // A structure of `type` in a new buffer of `bytes`.
  Level make_level(VkAccelerationStructureTypeKHR type, VkDeviceSize bytes, const char* name) {
    Level l;
    l.storage = StorageBuffer(*ctx, bytes, name, BufferBinding::kAddressOnly);
    l.device = ctx->device();
    l.destroy = vk.destroy;
    VkAccelerationStructureCreateInfoKHR ci{};
    ci.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR;
    ci.buffer = l.storage.handle();
    ci.size = bytes;
    ci.type = type;
    check_vk(vk.create(ctx->device(), &ci, nullptr, &l.handle),
             std::string("vkCreateAccelerationStructureKHR (") + name + ")");
    return l;
  }

  // Sizes of a build of `geometry` with `count` primitives.
  VkAccelerationStructureBuildSizesInfoKHR sizes(VkAccelerationStructureBuildGeometryInfoKHR& info,
                                                 std::uint32_t count) const {
    VkAccelerationStructureBuildSizesInfoKHR s{};
    s.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR;
    vk.build_sizes(ctx->device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info, &count,
                   &s);
    return s;
  }

  // A scratch buffer of `bytes`, and its address aligned as the driver asks.
  StorageBuffer scratch(VkDeviceSize bytes, VkDeviceAddress* address) {
    VkPhysicalDeviceAccelerationStructurePropertiesKHR as{};
    as.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR;
    VkPhysicalDeviceProperties2 p2{};
    p2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
    p2.pNext = &as;
    vkGetPhysicalDeviceProperties2(ctx->physical_device(), &p2);
    const VkDeviceSize align = std::max<VkDeviceSize>(as.minAccelerationStructureScratchOffsetAlignment, 1);
    StorageBuffer b(*ctx, bytes + align, "acceleration structure scratch",
                    BufferBinding::kAddressOnly);
    *address = (b.device_address() + align - 1) / align * align;
    stats.scratch_bytes = std::max<std::uint64_t>(stats.scratch_bytes, bytes);
    return b;
  }

  void build_bottom(std::span<const glm::vec3> vertices) {
    const auto count = static_cast<std::uint32_t>(vertices.size() / 3);
    StorageBuffer input(*ctx, std::max<std::size_t>(vertices.size_bytes(), 16),
                        "acceleration structure vertices", BufferBinding::kAddressOnly);
    input.upload(vertices.data(), vertices.size_bytes());
    VkAccelerationStructureGeometryKHR g{};
    g.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR;
    g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
    g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
    auto& t = g.geometry.triangles;
    t.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
    t.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
    t.vertexData.deviceAddress = input.device_address();
    t.vertexStride = sizeof(glm::vec3);
    t.maxVertex = count == 0 ? 0 : 3 * count - 1;
    t.indexType = VK_INDEX_TYPE_NONE_KHR;
    VkAccelerationStructureBuildGeometryInfoKHR info{};
    info.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR;
    info.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
    info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR |
                 VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_COMPACTION_BIT_KHR;
    info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
    info.geometryCount = 1;
    info.pGeometries = &g;
    const VkAccelerationStructureBuildSizesInfoKHR need = sizes(info, count);
    Level built = make_level(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
                             need.accelerationStructureSize, "bottom-level acceleration structure");
    StorageBuffer scratch_buffer = scratch(need.buildScratchSize, &info.scratchData.deviceAddress);
    info.dstAccelerationStructure = built.handle;
    const VkAccelerationStructureBuildRangeInfoKHR range{count, 0, 0, 0};
    const VkAccelerationStructureBuildRangeInfoKHR* ranges = &range;

    VkQueryPoolCreateInfo qi{};
    qi.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    qi.queryType = VK_QUERY_TYPE_ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR;
    qi.queryCount = 1;
    VkQueryPool pool = VK_NULL_HANDLE;
    check_vk(vkCreateQueryPool(ctx->device(), &qi, nullptr, &pool), "vkCreateQueryPool");
    VkDeviceSize compacted = 0;
    try {
      ctx->submit_and_wait(
          [&](VkCommandBuffer cmd) {
            build_barrier(cmd, kBuildStage, kBuildReads);
            vk.build(cmd, 1, &info, &ranges);
            build_barrier(cmd, kBuildStage, kBuildReads);
            vkCmdResetQueryPool(cmd, pool, 0, 1);
            vk.write_properties(cmd, 1, &built.handle,
                                VK_QUERY_TYPE_ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR, pool, 0);
          },
          "the bottom-level acceleration structure's build");
      check_vk(vkGetQueryPoolResults(ctx->device(), pool, 0, 1, sizeof compacted, &compacted,
                                     sizeof compacted,
                                     VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
               "vkGetQueryPoolResults (compacted size)");
    } catch (...) {
      vkDestroyQueryPool(ctx->device(), pool, nullptr);
      throw;
    }
    vkDestroyQueryPool(ctx->device(), pool, nullptr);
    stats.uncompacted_bytes = need.accelerationStructureSize;
    compact(std::move(built), compacted);
  }

  // `built` copied into a structure of `bytes` (its compacted size), then freed.
  void compact(Level built, VkDeviceSize bytes) {
    bottom = make_level(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
                        std::max<VkDeviceSize>(bytes, 256),
                        "bottom-level acceleration structure (compacted)");
    VkCopyAccelerationStructureInfoKHR ci{};
    ci.sType = VK_STRUCTURE_TYPE_COPY_ACCELERATION_STRUCTURE_INFO_KHR;
    ci.src = built.handle;
    ci.dst = bottom.handle;
    ci.mode = VK_COPY_ACCELERATION_STRUCTURE_MODE_COMPACT_KHR;
    ctx->submit_and_wait(
        [&](VkCommandBuffer cmd) {
          build_barrier(cmd, kBuildStage, kBuildReads);
          vk.copy(cmd, &ci);
        },
        "the bottom-level acceleration structure's compaction");
    stats.bytes = bottom.storage.size();
  }

  void build_top() {
    VkAccelerationStructureDeviceAddressInfoKHR ai{};
    ai.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR;
    ai.accelerationStructure = bottom.handle;
    VkAccelerationStructureInstanceKHR instance{};
    instance.transform.matrix[0][0] = instance.transform.matrix[1][1] =
        instance.transform.matrix[2][2] = 1.0f;
    instance.mask = 0xFF;
    instance.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR |
                     VK_GEOMETRY_INSTANCE_FORCE_OPAQUE_BIT_KHR;
    instance.accelerationStructureReference = vk.address(ctx->device(), &ai);
    StorageBuffer input(*ctx, sizeof instance, "acceleration structure instance",
                        BufferBinding::kAddressOnly);
    input.upload(&instance, sizeof instance);

    VkAccelerationStructureGeometryKHR g{};
    g.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR;
    g.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
    g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
    g.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
    g.geometry.instances.data.deviceAddress = input.device_address();
    VkAccelerationStructureBuildGeometryInfoKHR info{};
    info.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR;
    info.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
    info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
    info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
    info.geometryCount = 1;
    info.pGeometries = &g;
    const VkAccelerationStructureBuildSizesInfoKHR need = sizes(info, 1);
    top = make_level(VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, need.accelerationStructureSize,
                     "top-level acceleration structure");
    StorageBuffer scratch_buffer = scratch(need.buildScratchSize, &info.scratchData.deviceAddress);
    info.dstAccelerationStructure = top.handle;
    const VkAccelerationStructureBuildRangeInfoKHR range{1, 0, 0, 0};
    const VkAccelerationStructureBuildRangeInfoKHR* ranges = &range;
    ctx->submit_and_wait(
        [&](VkCommandBuffer cmd) {
          build_barrier(cmd, kBuildStage, kBuildReads);
          vk.build(cmd, 1, &info, &ranges);
          // The kernels' ray queries read it.
          build_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR);
        },
        "the top-level acceleration structure's build");
    stats.bytes += top.storage.size();
    stats.uncompacted_bytes += top.storage.size();
  }
};

AccelerationStructure::AccelerationStructure(VulkanContext& ctx,
                                             std::span<const glm::vec3> vertices)
    : s_(std::make_unique<State>(ctx, vertices)) {}
AccelerationStructure::~AccelerationStructure() = default;
AccelerationStructure::AccelerationStructure(AccelerationStructure&&) noexcept = default;
AccelerationStructure& AccelerationStructure::operator=(AccelerationStructure&&) noexcept =
    default;

VkAccelerationStructureKHR AccelerationStructure::top() const { return s_->top.handle; }
const AccelerationStructureStats& AccelerationStructure::stats() const { return s_->stats; }

}  // namespace hrpp
