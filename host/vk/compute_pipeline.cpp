#include "vk/compute_pipeline.h"

#include <map>
#include <vector>

#include "common/error.h"
#include "vk/float_controls.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"
#include "vk/vulkan_context.h"

namespace hrpp {

struct ComputePipeline::State {
  VkDevice device = VK_NULL_HANDLE;
  Kernel kernel{};
  std::string name;  // the kernel's, for error messages
  std::uint32_t push_bytes = 0;
  VkShaderModule module = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
  std::vector<VkDescriptorType> types;  // per binding

  // The constructor's steps, in order; each throws naming the kernel.
  void create_module(std::span<const std::uint32_t> spirv, bool denorm_preserve);
  void create_layouts();
  void create_pipeline(std::span<const SpecializationConstant> specialization);
  void create_descriptor_set();
  std::string what() const { return " (" + name + ")"; }

  ~State() {
    if (!device) return;
    if (pipeline) vkDestroyPipeline(device, pipeline, nullptr);
    if (pool) vkDestroyDescriptorPool(device, pool, nullptr);
    if (layout) vkDestroyPipelineLayout(device, layout, nullptr);
    if (set_layout) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
    if (module) vkDestroyShaderModule(device, module, nullptr);
  }
};

ComputePipeline::ComputePipeline(VulkanContext& ctx, Kernel kernel,
                                 std::span<const std::uint32_t> spirv, std::uint32_t binding_count,
                                 std::uint32_t push_constant_bytes,
                                 std::span<const SpecializationConstant> specialization)
    : ComputePipeline(
          ctx, kernel, spirv,
          std::vector<VkDescriptorType>(binding_count, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),
          push_constant_bytes, specialization) {}

// With DenormPreserve where the device offers it (vk/float_controls.h).
void ComputePipeline::State::create_module(std::span<const std::uint32_t> spirv,
                                           bool denorm_preserve) {
  std::vector<std::uint32_t> preserving;
  if (denorm_preserve) {
    preserving = with_denorm_preserve(spirv);
    spirv = preserving;
  }
  VkShaderModuleCreateInfo mci{};
  mci.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
  mci.codeSize = spirv.size_bytes();
  mci.pCode = spirv.data();
  check_vk(vkCreateShaderModule(device, &mci, nullptr, &module), "vkCreateShaderModule" + what());
}

// One descriptor set layout (binding i: types[i]) and the pipeline layout with the push range.
void ComputePipeline::State::create_layouts() {
  const auto binding_count = static_cast<std::uint32_t>(types.size());
  std::vector<VkDescriptorSetLayoutBinding> bindings(binding_count);
  for (std::uint32_t i = 0; i < binding_count; ++i) {
    bindings[i] = {};
    bindings[i].binding = i;
    bindings[i].descriptorType = types[i];
    bindings[i].descriptorCount = 1;
    bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo dli{};
  dli.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  dli.bindingCount = binding_count;
  dli.pBindings = bindings.data();
  check_vk(vkCreateDescriptorSetLayout(device, &dli, nullptr, &set_layout),
           "vkCreateDescriptorSetLayout" + what());

  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
  VkPipelineLayoutCreateInfo pli{};
  pli.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  pli.setLayoutCount = 1;
  pli.pSetLayouts = &set_layout;
  pli.pushConstantRangeCount = push_bytes ? 1 : 0;
  pli.pPushConstantRanges = &range;
  check_vk(vkCreatePipelineLayout(device, &pli, nullptr, &layout),
           "vkCreatePipelineLayout" + what());
}

void ComputePipeline::State::create_pipeline(
    std::span<const SpecializationConstant> specialization) {
  std::vector<VkSpecializationMapEntry> entries;
  std::vector<std::uint32_t> values;
  for (const SpecializationConstant& c : specialization) {
    entries.push_back({c.id, static_cast<std::uint32_t>(values.size() * 4), 4});
    values.push_back(c.value);
  }
  VkSpecializationInfo spec{};
  spec.mapEntryCount = static_cast<std::uint32_t>(entries.size());
  spec.pMapEntries = entries.data();
  spec.dataSize = values.size() * 4;
  spec.pData = values.data();
  VkComputePipelineCreateInfo cpi{};
  cpi.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
  cpi.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  cpi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cpi.stage.module = module;
  cpi.stage.pName = "main";
  cpi.stage.pSpecializationInfo = entries.empty() ? nullptr : &spec;
  cpi.layout = layout;
  check_vk(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &cpi, nullptr, &pipeline),
           "vkCreateComputePipelines" + what());
}

// A pool sized for one set of these bindings, and the set.
void ComputePipeline::State::create_descriptor_set() {
  std::map<VkDescriptorType, std::uint32_t> per_type;
  for (VkDescriptorType t : types) ++per_type[t];
  std::vector<VkDescriptorPoolSize> sizes;
  for (const auto& [type, count] : per_type) sizes.push_back({type, count});
  if (sizes.empty()) sizes.push_back({VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1});
  VkDescriptorPoolCreateInfo dpi{};
  dpi.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  dpi.maxSets = 1;
  dpi.poolSizeCount = static_cast<std::uint32_t>(sizes.size());
  dpi.pPoolSizes = sizes.data();
  check_vk(vkCreateDescriptorPool(device, &dpi, nullptr, &pool), "vkCreateDescriptorPool" + what());
  VkDescriptorSetAllocateInfo dai{};
  dai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  dai.descriptorPool = pool;
  dai.descriptorSetCount = 1;
  dai.pSetLayouts = &set_layout;
  check_vk(vkAllocateDescriptorSets(device, &dai, &set), "vkAllocateDescriptorSets" + what());
}

ComputePipeline::ComputePipeline(VulkanContext& ctx, Kernel kernel,
                                 std::span<const std::uint32_t> spirv,
                                 std::span<const VkDescriptorType> binding_types,
                                 std::uint32_t push_constant_bytes,
                                 std::span<const SpecializationConstant> specialization)
    : s_(std::make_unique<State>()) {
  State& s = *s_;
  s.device = ctx.device();
  s.kernel = kernel;
  s.name = kernel_name(kernel);
  s.push_bytes = push_constant_bytes;
  s.types.assign(binding_types.begin(), binding_types.end());
  s.create_module(spirv, ctx.info().denorm_preserve);
  s.create_layouts();
  s.create_pipeline(specialization);
  s.create_descriptor_set();
}

ComputePipeline::~ComputePipeline() = default;
ComputePipeline::ComputePipeline(ComputePipeline&&) noexcept = default;
ComputePipeline& ComputePipeline::operator=(ComputePipeline&&) noexcept = default;

void ComputePipeline::bind(std::uint32_t binding, const StorageBuffer& buffer) {
  if (buffer.binding() != BufferBinding::kStorage)
    throw Error(s_->name + ": " + buffer.name() +
                (buffer.binding() == BufferBinding::kTexelOnly
                     ? " is read through texel views only"
                     : " is reached by its device address only") +
                " and cannot be bound as a storage buffer");
  VkDescriptorBufferInfo info{buffer.handle(), 0, VK_WHOLE_SIZE};
  VkWriteDescriptorSet w{};
  w.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
  w.dstSet = s_->set;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  w.pBufferInfo = &info;
  vkUpdateDescriptorSets(s_->device, 1, &w, 0, nullptr);
}

void ComputePipeline::bind(std::uint32_t binding, const TexelView& view) {
  const VkBufferView handle = view.handle();
  VkWriteDescriptorSet w{};
  w.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
  w.dstSet = s_->set;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = s_->types.at(binding);  // uniform or storage texel buffer
  w.pTexelBufferView = &handle;
  vkUpdateDescriptorSets(s_->device, 1, &w, 0, nullptr);
}

void ComputePipeline::bind(std::uint32_t binding, VkAccelerationStructureKHR structure) {
  VkWriteDescriptorSetAccelerationStructureKHR as{};
  as.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR;
  as.accelerationStructureCount = 1;
  as.pAccelerationStructures = &structure;
  VkWriteDescriptorSet w{};
  w.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
  w.pNext = &as;
  w.dstSet = s_->set;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
  vkUpdateDescriptorSets(s_->device, 1, &w, 0, nullptr);
}

Kernel ComputePipeline::kernel() const { return s_->kernel; }
VkPipeline ComputePipeline::pipeline() const { return s_->pipeline; }
VkPipelineLayout ComputePipeline::layout() const { return s_->layout; }
VkDescriptorSet ComputePipeline::descriptor_set() const { return s_->set; }
std::uint32_t ComputePipeline::push_constant_bytes() const { return s_->push_bytes; }

struct KernelTimer::State {
  VkDevice device = VK_NULL_HANDLE;
  VkQueryPool pool = VK_NULL_HANDLE;
  std::uint32_t capacity = 0;  // dispatches
  double period_ns = 0.0;
  std::vector<TimerLabel> kernels;  // of the dispatches since reset()

  ~State() {
    if (pool) vkDestroyQueryPool(device, pool, nullptr);
  }
};

KernelTimer::KernelTimer(VulkanContext& ctx, std::uint32_t max_dispatches)
    : s_(std::make_unique<State>()) {
  s_->device = ctx.device();
  s_->capacity = max_dispatches;
  s_->period_ns = ctx.info().timestamp_period_ns;
  if (!ctx.info().timestamps) return;
  VkQueryPoolCreateInfo qpi{};
  qpi.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
  qpi.queryType = VK_QUERY_TYPE_TIMESTAMP;
  qpi.queryCount = 2 * max_dispatches;
  check_vk(vkCreateQueryPool(s_->device, &qpi, nullptr, &s_->pool), "vkCreateQueryPool");
}

KernelTimer::~KernelTimer() = default;
KernelTimer::KernelTimer(KernelTimer&&) noexcept = default;
KernelTimer& KernelTimer::operator=(KernelTimer&&) noexcept = default;

bool KernelTimer::has_timestamps() const { return s_->pool != VK_NULL_HANDLE; }

void KernelTimer::reset(VkCommandBuffer cmd) {
  s_->kernels.clear();
  if (s_->pool) vkCmdResetQueryPool(cmd, s_->pool, 0, 2 * s_->capacity);
}

void KernelTimer::begin(VkCommandBuffer cmd, const TimerLabel& label) {
  if (s_->kernels.size() >= s_->capacity)
    throw Error("KernelTimer: more than " + std::to_string(s_->capacity) +
                " timed dispatches in one submit");
  s_->kernels.push_back(label);
  if (s_->pool)
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, s_->pool,
                        static_cast<std::uint32_t>(2 * (s_->kernels.size() - 1)));
}

void KernelTimer::end(VkCommandBuffer cmd) {
  if (s_->pool)
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, s_->pool,
                        static_cast<std::uint32_t>(2 * s_->kernels.size() - 1));
}

std::map<TimerLabel, double> KernelTimer::read_ms() const {
  std::map<TimerLabel, double> ms;
  const std::uint32_t n = static_cast<std::uint32_t>(s_->kernels.size());
  if (n == 0) return ms;
  std::vector<std::uint64_t> ticks(2 * n, 0);
  if (s_->pool)
    check_vk(vkGetQueryPoolResults(s_->device, s_->pool, 0, 2 * n, ticks.size() * 8, ticks.data(),
                                   8, VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
             "vkGetQueryPoolResults");
  for (std::uint32_t i = 0; i < n; ++i)
    ms[s_->kernels[i]] += static_cast<double>(ticks[2 * i + 1] - ticks[2 * i]) * s_->period_ns * 1e-6;
  return ms;
}

namespace {

void bind_and_push(VkCommandBuffer cmd, const ComputePipeline& pipeline, const void* push) {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.pipeline());
  const VkDescriptorSet set = pipeline.descriptor_set();
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout(), 0, 1, &set, 0,
                          nullptr);
  if (pipeline.push_constant_bytes())
    vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0,
                       pipeline.push_constant_bytes(), push);
}

// One global memory barrier: writes of `src_stages` (`src_access`) made visible to `dst_stages`.
void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src_stages,
                    VkAccessFlags src_access, VkPipelineStageFlags dst_stages,
                    VkAccessFlags dst_access) {
  VkMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cmd, src_stages, dst_stages, 0, 1, &b, 0, nullptr, 0, nullptr);
}

void compute_to_compute_barrier(VkCommandBuffer cmd) {
  memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

}  // namespace

void record_dispatch(VkCommandBuffer cmd, const ComputePipeline& pipeline, const void* push,
                     std::uint32_t groups, KernelTimer* timer, std::optional<TimerLabel> label) {
  bind_and_push(cmd, pipeline, push);
  if (timer) timer->begin(cmd, label.value_or(TimerLabel{pipeline.kernel()}));
  vkCmdDispatch(cmd, groups, 1, 1);
  if (timer) timer->end(cmd);
  compute_to_compute_barrier(cmd);
}

void record_dispatch_indirect(VkCommandBuffer cmd, const ComputePipeline& pipeline,
                              const void* push, const StorageBuffer& args, VkDeviceSize offset,
                              KernelTimer* timer, std::optional<TimerLabel> label) {
  bind_and_push(cmd, pipeline, push);
  if (timer) timer->begin(cmd, label.value_or(TimerLabel{pipeline.kernel()}));
  vkCmdDispatchIndirect(cmd, args.handle(), offset);
  if (timer) timer->end(cmd);
  compute_to_compute_barrier(cmd);
}

void record_update(VkCommandBuffer cmd, const StorageBuffer& dst, VkDeviceSize offset,
                   VkDeviceSize bytes, const void* data) {
  vkCmdUpdateBuffer(cmd, dst.handle(), offset, bytes, data);
}

void record_copy(VkCommandBuffer cmd, const StorageBuffer& src, VkDeviceSize src_offset,
                 const StorageBuffer& dst, VkDeviceSize dst_offset, VkDeviceSize bytes) {
  const VkBufferCopy region{src_offset, dst_offset, bytes};
  vkCmdCopyBuffer(cmd, src.handle(), dst.handle(), 1, &region);
}

void transfer_compute_barrier(VkCommandBuffer cmd) {
  memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                 VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                 VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                     VK_PIPELINE_STAGE_HOST_BIT,
                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                     VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                     VK_ACCESS_HOST_READ_BIT);
}

void indirect_args_barrier(VkCommandBuffer cmd) {
  memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                 VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                 VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

}  // namespace hrpp
