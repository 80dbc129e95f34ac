#include "gpu/gpu_predictor.h"

#include <algorithm>
#include <string>
#include <vector>

#include "common/error.h"
#include "gpu/compute_pipeline.h"
#include "gpu/embedded_shaders.h"
#include "gpu/storage_buffer.h"
#include "gpu/vulkan_context.h"
#include "hrpp/prediction_node.h"

namespace hrpp {

static_assert(sizeof(gpu::InsertPushConstants) == 16);

namespace {

// One predictor's buffers (hit-all or hit-any).
struct Table {
  gpu::PredictorParams params{};
  StorageBuffer param_buf, tags, stamps, slots, requests, counters;
  ComputePipeline insert;

  Table(VulkanContext& ctx, const gpu::PredictorParams& p, const char* which)
      : params(p),
        param_buf(ctx, sizeof(gpu::PredictorParams), std::string(which) + " predictor parameters"),
        tags(ctx, std::size_t{p.sets} * p.ways * sizeof(std::uint64_t),
             std::string(which) + " predictor tags (--table-sets × --table-ways)"),
        stamps(ctx, std::size_t{p.sets} * p.ways * sizeof(std::uint32_t),
               std::string(which) + " predictor stamps"),
        slots(ctx, std::size_t{p.sets} * p.ways * p.nodes * sizeof(std::uint32_t),
              std::string(which) + " predictor node slots (sets × ways × --table-nodes)"),
        requests(ctx, sizeof(gpu::InsertRequest), "insert requests"),
        counters(ctx, sizeof(gpu::PredictorCounters), std::string(which) + " predictor counters"),
        insert(ctx, "hrpp_insert", embedded_spirv("hrpp_insert"), HRPP_TABLE_BINDING_COUNT,
               sizeof(gpu::InsertPushConstants)) {
    clear();
    insert.bind(HRPP_TABLE_PARAMS, param_buf);
    insert.bind(HRPP_TABLE_TAGS, tags);
    insert.bind(HRPP_TABLE_STAMPS, stamps);
    insert.bind(HRPP_TABLE_SLOTS, slots);
    insert.bind(HRPP_TABLE_REQUESTS, requests);
    insert.bind(HRPP_TABLE_COUNTERS, counters);
  }

  void clear() {
    tags.fill(0xFFFFFFFFu);  // all-ones tags: empty
    stamps.fill(0u);
    slots.fill(static_cast<std::uint32_t>(HRPP_EMPTY_NODE));
  }

  void bind_to(ComputePipeline& p) const {
    p.bind(HRPP_PREDICT_BINDING_FIRST + HRPP_TABLE_PARAMS, param_buf);
    p.bind(HRPP_PREDICT_BINDING_FIRST + HRPP_TABLE_TAGS, tags);
    p.bind(HRPP_PREDICT_BINDING_FIRST + HRPP_TABLE_STAMPS, stamps);
    p.bind(HRPP_PREDICT_BINDING_FIRST + HRPP_TABLE_SLOTS, slots);
    p.bind(HRPP_PREDICT_BINDING_FIRST + HRPP_TABLE_REQUESTS, requests);
    p.bind(HRPP_PREDICT_BINDING_FIRST + HRPP_TABLE_COUNTERS, counters);
  }
};

void barrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access,
             VkPipelineStageFlags dst, VkAccessFlags dst_access) {
  VkMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &b, 0, nullptr, 0, nullptr);
}

}  // namespace

struct GpuPredictor::State {
  VulkanContext* ctx;
  PredictorConfig config;
  StorageBuffer node_of_prim;
  std::unique_ptr<Table> all, any;

  Table& table(bool any_hit) { return any_hit ? *any : *all; }
  const Table& table(bool any_hit) const { return any_hit ? *any : *all; }
};

GpuPredictor::GpuPredictor(VulkanContext& ctx, const GpuBvh& bvh, const PredictorConfig& config)
    : s_(std::make_unique<State>()) {
  if (!ctx.info().int64 || !ctx.info().int64_atomics)
    throw Error(ctx.info().name + ": --hrpp on needs shaderInt64 and shaderBufferInt64Atomics");
  if (config.batch > HRPP_INSERT_BATCH_MAX)
    throw Error("--hrpp-batch: at most " + std::to_string(HRPP_INSERT_BATCH_MAX) + " rays");
  s_->ctx = &ctx;
  s_->config = config;
  gpu::PredictorParams params = make_predictor_params(config, bvh.bounds);
  params.serial = config.serial ? 1u : 0u;
  // The node to insert for each triangle id: the go-up level applied once, here.
  const std::vector<std::uint32_t> leaves = leaf_of_prim(bvh);
  std::vector<std::int32_t> nodes(leaves.size(), HRPP_EMPTY_NODE);
  for (std::size_t p = 0; p < leaves.size(); ++p)
    if (leaves[p] != kNoLeaf) nodes[p] = prediction_node(bvh, leaves[p], config.go_up);
  s_->node_of_prim = StorageBuffer(ctx, nodes.size() * sizeof(std::int32_t), "node of triangle");
  s_->node_of_prim.upload(std::span<const std::int32_t>(nodes));
  s_->all = std::make_unique<Table>(ctx, params, "hit-all");
  s_->any = std::make_unique<Table>(ctx, params, "hit-any");
}

GpuPredictor::~GpuPredictor() = default;
GpuPredictor::GpuPredictor(GpuPredictor&&) noexcept = default;
GpuPredictor& GpuPredictor::operator=(GpuPredictor&&) noexcept = default;

const PredictorConfig& GpuPredictor::config() const { return s_->config; }

void GpuPredictor::bind(ComputePipeline& pipeline, bool any_hit, std::size_t rays) {
  Table& t = s_->table(any_hit);
  const std::size_t bytes = std::max<std::size_t>(rays, 1) * sizeof(gpu::InsertRequest);
  if (t.requests.size() < bytes) {
    t.requests = StorageBuffer();
    t.requests = StorageBuffer(*s_->ctx, bytes, "insert requests");
    t.insert.bind(HRPP_TABLE_REQUESTS, t.requests);
  }
  t.bind_to(pipeline);
  pipeline.bind(HRPP_PREDICT_BINDING_FIRST + HRPP_PREDICT_NODE_OF_PRIM, s_->node_of_prim);
}

void GpuPredictor::begin_trace(bool any_hit) {
  const gpu::PredictorCounters zero{};
  s_->table(any_hit).counters.upload(&zero, sizeof zero);
}

void GpuPredictor::set_clock(bool any_hit, std::uint32_t clock) {
  Table& t = s_->table(any_hit);
  t.params.clock = clock;
  t.param_buf.upload(&t.params, sizeof t.params);
}

std::uint32_t GpuPredictor::rays_per_workgroup(std::uint32_t rays_per_invocation) const {
  const std::uint32_t sub = std::max(s_->ctx->info().subgroup_size, 1u);
  const std::uint32_t lanes =
      s_->config.serial ? std::max(HRPP_TRACE_WORKGROUP_SIZE / sub, 1u) : HRPP_TRACE_WORKGROUP_SIZE;
  return lanes * rays_per_invocation;
}

void GpuPredictor::record_batches(VkCommandBuffer cmd, ComputePipeline& trace,
                                  const gpu::TracePushConstants& pc, StorageBuffer& counters,
                                  bool any_hit, std::uint32_t count, std::uint32_t clock) {
  Table& t = s_->table(any_hit);
  const std::uint32_t per_group = rays_per_workgroup(pc.rays_per_invocation);
  for (std::uint32_t first = 0; first < count; first += s_->config.batch) {
    const std::uint32_t n = std::min(s_->config.batch, count - first);
    // The batch's rays: the cursor starts at `first`, the kernel stops at first + n.
    barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
            VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    const std::uint32_t end = first + n;
    vkCmdUpdateBuffer(cmd, counters.handle(), offsetof(gpu::TraceCounters, next_ray),
                      sizeof(std::uint32_t), &first);
    vkCmdUpdateBuffer(cmd, counters.handle(), offsetof(gpu::TraceCounters, ray_count),
                      sizeof(std::uint32_t), &end);
    barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    record_dispatch(cmd, trace, &pc, (n + per_group - 1) / per_group, nullptr);
    const gpu::InsertPushConstants ipc{first, n, clock + first, 0};
    record_dispatch(cmd, t.insert, &ipc, 1, nullptr);
  }
}

gpu::PredictorCounters GpuPredictor::counters(bool any_hit) const {
  gpu::PredictorCounters c{};
  s_->table(any_hit).counters.download(&c, sizeof c);
  return c;
}

TableOccupancy GpuPredictor::occupancy(bool any_hit) const {
  const Table& t = s_->table(any_hit);
  TableOccupancy o;
  o.capacity = std::uint64_t{t.params.sets} * t.params.ways;
  o.bytes = s_->config.table.bytes();
  std::vector<std::uint64_t> tags(o.capacity);
  t.tags.download(std::span<std::uint64_t>(tags));
  std::vector<std::uint32_t> slots(o.capacity * t.params.nodes);
  t.slots.download(std::span<std::uint32_t>(slots));
  for (std::uint64_t e = 0; e < o.capacity; ++e) {
    if (tags[e] == ~std::uint64_t{0}) continue;
    ++o.entries;
    for (std::uint32_t s = 0; s < t.params.nodes; ++s)
      if (slots[e * t.params.nodes + s] != static_cast<std::uint32_t>(HRPP_EMPTY_NODE)) ++o.nodes;
  }
  return o;
}

void GpuPredictor::set_count_baseline(bool on) {
  s_->config.count_baseline = on;
  s_->all->params.count_baseline = s_->any->params.count_baseline = on ? 1u : 0u;
}

void GpuPredictor::clear() {
  s_->all->clear();
  s_->any->clear();
}

}  // namespace hrpp
