#include "front/gpu_predictor.h"

#include <algorithm>
#include <array>
#include <optional>
#include <utility>
#include <cstddef>
#include <string>
#include <vector>

#include "common/error.h"
#include "vk/compute_pipeline.h"
#include "kernels/device_bvh.h"
#include "vk/embedded_shaders.h"
#include "kernels/kernel_bindings.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"
#include "kernels/trace_counters.h"
#include "vk/vulkan_context.h"
#include "kernels/trace_lanes.h"
#include "hrpp/prediction_node.h"
#include "hrpp_table_set.h"

namespace hrpp {

static_assert(sizeof(gpu::InsertPushConstants) == 16);
static_assert(sizeof(gpu::StagePushConstants) == 24);
static_assert(sizeof(gpu::PredictQueue) == 80);
static_assert(sizeof(gpu::QueueEntry) == 16);

namespace {

// The queue at the start of a trace (or a batch): empty, indirect dispatches of (0, 1, 1).
gpu::PredictQueue empty_queue(std::uint32_t next_ray, std::uint32_t ray_count) {
  gpu::PredictQueue q{};
  q.next_ray = next_ray;
  q.ray_count = ray_count;
  q.trace_groups[1] = q.trace_groups[2] = 1;
  q.resolve_groups[1] = q.resolve_groups[2] = 1;
  return q;
}

// Bytes rounded up to whole texels (the tags and slots are also read through texel views).
std::size_t texel_bytes(std::size_t bytes) {
  return (bytes + TexelView::kTexelBytes - 1) / TexelView::kTexelBytes * TexelView::kTexelBytes;
}

// A class's table buffers (each its own storage buffer, held to the limits on its own): the
// tags, the use stamps (with the distance gate, then the nearest hits) and the node slots.
enum TableBuffer { kTags, kStamps, kSlots };
std::array<BufferNeed, 3> table_buffers(RayClass c, std::uint64_t sets, std::uint64_t ways,
                                        std::uint64_t nodes, bool gate) {
  const std::string cls = ray_class_name(c);
  return {BufferNeed{cls + " predictor tags (table_sets × table_ways)",
                     texel_bytes(sets * ways * sizeof(std::uint64_t))},
          BufferNeed{cls + (gate ? " predictor stamps and nearest hits" : " predictor stamps"),
                     (gate ? 2u : 1u) * sets * ways * sizeof(std::uint32_t)},
          BufferNeed{cls + " predictor node slots (sets × ways × table_nodes)",
                     texel_bytes(sets * ways * nodes * sizeof(std::uint32_t))}};
}

}  // namespace

std::uint32_t predict_workgroup_size(std::uint32_t subgroup_size) {
  const bool divides = subgroup_size > 0 && subgroup_size <= HRPP_TRACE_WORKGROUP_SIZE &&
                       HRPP_TRACE_WORKGROUP_SIZE % subgroup_size == 0;
  return divides ? subgroup_size : HRPP_TRACE_WORKGROUP_SIZE;
}

namespace {

// One ray class's table and its kernels (bound to the table and to the class's query arrays).
// hrpp_predict of a class, specialised: interior-node verification only with go-up > 0, the
// counting traversal only in the variant that counts, one subgroup per workgroup.
ComputePipeline make_predict(VulkanContext& ctx, RayClass c, const gpu::PredictorParams& p,
                             bool counts, Fallback fallback) {
  const bool interior = p.go_up > 0 || p.go_up_size > 0.0f;
  const SpecializationConstant spec[] = {
      {HRPP_SPEC_VERIFY_INTERIOR, interior ? 1u : 0u},
      {HRPP_SPEC_COUNT_BASELINE, counts ? 1u : 0u},
      {HRPP_SPEC_PREDICT_WORKGROUP, predict_workgroup_size(ctx.info().subgroup_size)},
      {HRPP_SPEC_SKIP_LIST, fallback == Fallback::kSkip ? 1u : 0u}};
  return ComputePipeline(ctx, Kernel::hrpp_predict,
                         embedded_spirv(query_kind(c) == QueryKind::kAny ? Kernel::hrpp_predict_any
                                                                         : Kernel::hrpp_predict),
                         kStageBindingTypes, sizeof(gpu::StagePushConstants), spec);
}

struct Table {
  gpu::PredictorParams params{};
  StorageBuffer param_buf, tags, stamps, slots, requests, counters;
  TexelView tag_view, slot_view;
  ComputePipeline predicts[2];  // [counts the baseline]
  ComputePipeline resolve, insert;

  Table(VulkanContext& ctx, const gpu::PredictorParams& p, RayClass c, Fallback fallback)
      : Table(ctx, p, c, fallback,
              table_buffers(c, std::uint64_t{gpu::hrpp_table_count(p.sm_tables)} * p.sets,
                            p.ways, p.nodes, p.gate > 0.0f)) {}

  Table(VulkanContext& ctx, const gpu::PredictorParams& p, RayClass c, Fallback fallback,
        const std::array<BufferNeed, 3>& b)
      : params(p),
        param_buf(ctx, sizeof(gpu::PredictorParams), name(c, "predictor parameters"),
                  BufferBinding::kStorage, MemoryRole::kHostShared),  // written while recording
        tags(ctx, b[kTags]),
        stamps(ctx, b[kStamps]),
        slots(ctx, b[kSlots]),
        requests(ctx, sizeof(gpu::InsertRequest), "insert requests"),
        counters(ctx, sizeof(gpu::PredictorCounters), name(c, "predictor counters"),
                 BufferBinding::kStorage, MemoryRole::kHostShared),
        tag_view(ctx, tags),
        slot_view(ctx, slots),
        predicts{make_predict(ctx, c, p, false, fallback), make_predict(ctx, c, p, true, fallback)},
        resolve(ctx, Kernel::hrpp_resolve, embedded_spirv(Kernel::hrpp_resolve), kStageBindingTypes,
                sizeof(gpu::StagePushConstants)),
        insert(ctx, Kernel::hrpp_insert, embedded_spirv(Kernel::hrpp_insert),
               HRPP_TABLE_BINDING_COUNT, sizeof(gpu::InsertPushConstants)) {
    clear();
    upload_params();
    bind_table(insert, 0);
    for (ComputePipeline* k : stage_kernels()) {
      bind_table(*k, HRPP_STAGE_BINDING_TABLE);
      k->bind(HRPP_STAGE_BINDING_TAG_TEXELS, tag_view);
      k->bind(HRPP_STAGE_BINDING_SLOT_TEXELS, slot_view);
    }
  }

  // The kernels with the stage's bindings.
  std::array<ComputePipeline*, 3> stage_kernels() { return {&predicts[0], &predicts[1], &resolve}; }
  ComputePipeline& predict() { return predicts[params.count_baseline]; }

  static std::string name(RayClass c, const char* what) {
    return std::string(ray_class_name(c)) + " " + what;
  }

  void clear() {
    tags.fill(0xFFFFFFFFu);  // all-ones tags: empty
    stamps.fill(0u);
    slots.fill(static_cast<std::uint32_t>(HRPP_EMPTY_NODE));
  }

  void upload_params() { param_buf.upload(&params, sizeof params); }

  void bind_table(ComputePipeline& p, std::uint32_t base) const {
    p.bind(base + HRPP_TABLE_PARAMS, param_buf);
    p.bind(base + HRPP_TABLE_TAGS, tags);
    p.bind(base + HRPP_TABLE_STAMPS, stamps);
    p.bind(base + HRPP_TABLE_SLOTS, slots);
    p.bind(base + HRPP_TABLE_REQUESTS, requests);
    p.bind(base + HRPP_TABLE_COUNTERS, counters);
  }
};

// The queue of one query kind (hit-all: camera and bounce rays; hit-any: shadow rays) and the
// trace kernel bound to it.
struct Queue {
  StorageBuffer state;           // gpu::PredictQueue
  StorageBuffer trace_counters;  // gpu::TraceCounters of the trace over the queue
  StorageBuffer rays, entries, hits, skips;  // skips: the skip lists (fallback skip)
  TexelView ray_view, entry_view, hit_view, skip_view;
  QueueTraceKernel trace;     // the tracer's kernel for the queue (DeviceTracer::queue_kernel)
  ComputePipeline pass_args;  // hrpp_pass_args: predict_groups of a pilot or sample pass
  std::size_t capacity = 0;

  Queue(VulkanContext& ctx, QueueTraceKernel kernel)
      : state(ctx, sizeof(gpu::PredictQueue), "HRPP queue", BufferBinding::kStorage,
              MemoryRole::kHostShared),
        trace_counters(ctx, sizeof(gpu::TraceCounters), "HRPP queue trace counters",
                       BufferBinding::kStorage, MemoryRole::kHostShared),
        trace(std::move(kernel)),
        pass_args(ctx, Kernel::hrpp_pass_args, embedded_spirv(Kernel::hrpp_pass_args), 1,
                  sizeof(gpu::StagePushConstants)) {
    trace.pipeline.bind(trace.counters, trace_counters);
    pass_args.bind(0, state);
  }
};

// Bytes of a queue's per-ray arrays: ray, entry, hit and skip list.
constexpr std::size_t kQueueBytesPerRay =
    sizeof(gpu::Ray) + sizeof(gpu::QueueEntry) + sizeof(gpu::Hit) + TexelView::kTexelBytes;
static_assert(HRPP_SKIP_NODES * sizeof(std::int32_t) == TexelView::kTexelBytes);

// A node-of-triangle array's bytes for `prims` triangle ids: whole 16-byte texels, at least one.
std::uint64_t node_of_prim_bytes(std::uint64_t prims) {
  constexpr std::uint64_t kIdsPerTexel = TexelView::kTexelBytes / sizeof(std::int32_t);
  return std::max<std::uint64_t>(1, (prims + kIdsPerTexel - 1) / kIdsPerTexel) *
         TexelView::kTexelBytes;
}

// The distinct go-up rules (levels, size) of the predicting classes, in class order.
using GoUp = std::pair<std::uint32_t, float>;
GoUp go_up_of(const PredictorConfig& config, RayClass c) {
  return {config.go_up[c], config.go_up_size[c]};
}
std::vector<GoUp> go_up_levels(const PredictorConfig& config) {
  std::vector<GoUp> levels;
  for (RayClass c : kRayClasses)
    if (config.predicts(c) &&
        std::find(levels.begin(), levels.end(), go_up_of(config, c)) == levels.end())
      levels.push_back(go_up_of(config, c));
  return levels;
}

}  // namespace

struct GpuPredictor::State {
  VulkanContext* ctx;
  PredictorConfig config;
  // The node to insert for each triangle id, one array per go-up level that a predicting class
  // uses (classes with the same level share it), and the texel view hrpp_resolve reads it by.
  struct NodeOfPrim {
    GoUp level;
    StorageBuffer ids;
    TexelView view;
  };
  std::vector<NodeOfPrim> node_of_prim;
  PerClass<std::unique_ptr<Table>> tables;
  std::unique_ptr<Queue> queues[2];  // [index_of(QueryKind)]
  PerClass<Probe> probing{};         // how each class's next trace runs the stage
  PerClass<std::uint32_t> sample_stride{};  // a sample's stride (set_probing; 0: config.sample)
  PerClass<Probe> recorded{};        // how its last recorded trace ran it
  PerClass<std::uint32_t> clock{};   // use stamps (LRU): rays of the class traced so far

  Table& table(RayClass c) const { return *tables[c]; }
  const TexelView& node_of_prim_at(const GoUp& level) const {
    return std::find_if(node_of_prim.begin(), node_of_prim.end(),
                        [&](const NodeOfPrim& b) { return b.level == level; })
        ->view;
  }
  Queue& queue(QueryKind k) const { return *queues[index_of(k)]; }
  Queue& queue(RayClass c) const { return queue(query_kind(c)); }

  // The class's clock into its table's parameters: the use stamp of ray 0 of the next trace.
  void upload_clock(RayClass c) {
    Table& t = table(c);
    t.params.clock = clock[c];
    t.upload_params();
  }

  bool batched() const { return config.batch > 0; }

  std::uint32_t stride_of(RayClass c) const {
    return sample_stride[c] != 0 ? sample_stride[c] : config.sample;
  }

  // probing[c], with a sample read as off in batched mode (it has none).
  Probe probing_now(RayClass c) const {
    return probing[c] == Probe::kSample && batched() ? Probe::kOff : probing[c];
  }

  // `pilot_pass`: HRPP_PASS_*; `stride`: the sample's (0: the pilot schedule's K).
  gpu::StagePushConstants stage_push(const gpu::TracePushConstants& trace_pc,
                                     std::uint32_t pilot_pass = 0, std::uint32_t stride = 0) const {
    return {trace_pc.rays_per_invocation, trace_pc.canary_iterations,
            rays_per_workgroup(trace_pc.rays_per_invocation), stride ? stride : config.pilot,
            pilot_pass, 0};
  }

  // One round of predict → trace of the queue → resolve over the rays of `pilot_pass`
  // (HRPP_PASS_*: shaders/shared/hrpp_passes.h), timed under {kernel, `phase`, class}.
  void record_pass(VkCommandBuffer cmd, RayClass c, const RayCountSource& count,
                   const gpu::TracePushConstants& trace_pc, std::uint32_t pilot_pass,
                   KernelTimer* timer, std::uint32_t stride = 0, Phase phase = Phase::kRun) {
    // A pass over a fraction of the rays launches only the workgroups that have some: the
    // host's count sizes it, or hrpp_pass_args.comp on the device (not the trace's indirect
    // arguments, a workgroup per trace_group_rays of every ray).
    const bool fraction = pilot_pass == HRPP_PASS_PILOTS || pilot_pass == HRPP_PASS_SAMPLE;
    const gpu::StagePushConstants spc = stage_push(trace_pc, pilot_pass, stride);
    const TimerLabel label{Kernel::hrpp_predict, phase, c};
    if (count.host) {
      const std::uint32_t per_group = spc.trace_group_rays;
      const std::uint32_t n = gpu::hrpp_pass_ray_count(*count.host, pilot_pass, spc.pilot_stride);
      record_dispatch(cmd, table(c).predict(), &spc, (n + per_group - 1) / per_group, timer,
                      label);
    } else if (!fraction) {
      record_dispatch_indirect(cmd, table(c).predict(), &spc, *count.buffer, count.args_offset,
                               timer, label);
    } else {  // a fraction of the rays: only the workgroups that have some (timed as predict's)
      Queue& q = queue(c);
      record_dispatch(cmd, q.pass_args, &spc, 1, timer, label);
      indirect_args_barrier(cmd);
      record_dispatch_indirect(cmd, table(c).predict(), &spc, q.state,
                               offsetof(gpu::PredictQueue, predict_groups), timer, label);
    }
    record_queue_trace(cmd, c, trace_pc, timer, phase);
  }

  // Empties the queue (its cursors and indirect arguments) for another round; the answer counts
  // go on adding up. `rays` (first, end): also the rays to predict (a batch); else the same rays.
  void start_queue(VkCommandBuffer cmd, RayClass c, const RayCountSource& count);
  // The predicted trace of the class's rays (one round, or pilots then the others).
  void record_rounds(VkCommandBuffer cmd, RayClass c, const RayCountSource& count,
                     const gpu::TracePushConstants& trace_pc, KernelTimer* timer);
  // One round over every config.sample-th ray, then an empty predict dispatch.
  void record_sample(VkCommandBuffer cmd, RayClass c, const RayCountSource& count,
                     const gpu::TracePushConstants& trace_pc, KernelTimer* timer);
  // Batched mode: a round per batch of config.batch rays, inserts applied in ray order.
  void record_batches(VkCommandBuffer cmd, RayClass c, std::uint32_t count,
                      const gpu::TracePushConstants& trace_pc);

  void restart_queue(VkCommandBuffer cmd, RayClass c,
                     std::optional<std::pair<std::uint32_t, std::uint32_t>> rays = {}) {
    Queue& q = queue(c);
    const gpu::PredictQueue empty = rays ? empty_queue(rays->first, rays->second) : empty_queue(0, 0);
    const std::uint32_t zero = 0;
    transfer_compute_barrier(cmd);
    if (rays) {  // next_ray, ray_count, queued
      record_update(cmd, q.state, 0, 3 * sizeof(std::uint32_t), &empty);
    } else {
      record_update(cmd, q.state, offsetof(gpu::PredictQueue, next_ray), sizeof zero, &zero);
      record_update(cmd, q.state, offsetof(gpu::PredictQueue, queued), sizeof zero, &zero);
    }
    record_update(cmd, q.state, offsetof(gpu::PredictQueue, trace_groups),
                  sizeof empty.trace_groups + sizeof empty.resolve_groups, &empty.trace_groups);
    record_update(cmd, q.trace_counters, offsetof(gpu::TraceCounters, next_ray), sizeof zero,
                  &zero);
    transfer_compute_barrier(cmd);
  }

  std::uint32_t rays_per_workgroup(std::uint32_t rays_per_invocation) const {
    return trace_lanes(config.serial, ctx->info().subgroup_size) * rays_per_invocation;
  }

  // The trace over the queue and the resolve pass, after hrpp_predict: the trace's ray count
  // is the queue's size, both dispatched indirectly from the queue.
  void record_queue_trace(VkCommandBuffer cmd, RayClass c, const gpu::TracePushConstants& trace_pc,
                          KernelTimer* timer, Phase phase = Phase::kRun) {
    Queue& q = queue(c);
    indirect_args_barrier(cmd);
    record_copy(cmd, q.state, offsetof(gpu::PredictQueue, queued), q.trace_counters,
                offsetof(gpu::TraceCounters, ray_count), sizeof(std::uint32_t));
    transfer_compute_barrier(cmd);
    record_dispatch_indirect(cmd, q.trace.pipeline, &trace_pc, q.state,
                             offsetof(gpu::PredictQueue, trace_groups), timer,
                             TimerLabel{q.trace.pipeline.kernel(), phase, c});
    const gpu::StagePushConstants spc = stage_push(trace_pc);
    record_dispatch_indirect(cmd, table(c).resolve, &spc, q.state,
                             offsetof(gpu::PredictQueue, resolve_groups), timer,
                             TimerLabel{Kernel::hrpp_resolve, phase, c});
  }
};

std::vector<BufferNeed> GpuPredictor::buffer_needs(const GpuBvh& bvh, const PredictorConfig& config,
                                                   std::size_t capacity) {
  std::uint64_t prims = 0;  // leaf_of_prim's length: the largest triangle id + 1
  for (const gpu::TriangleRecord& t : bvh.triangles) prims = std::max<std::uint64_t>(prims, t.prim + 1);
  std::vector<BufferNeed> needs;
  for (std::size_t i = 0; i < go_up_levels(config).size(); ++i)
    needs.push_back({"node of triangle", node_of_prim_bytes(prims), BufferBinding::kTexelOnly});
  std::uint64_t request_bytes = 0;
  for (RayClass c : kRayClasses) {
    if (!config.predicts(c)) continue;
    const TableConfig& t = config.table[c];
    for (const BufferNeed& b : table_buffers(c, std::uint64_t{t.sets} * t.sm_tables, t.ways,
                                             t.nodes, config.gate[c] > 0.0f))
      needs.push_back(b);
    request_bytes += capacity * sizeof(gpu::InsertRequest);
  }
  needs.push_back(
      {"HRPP queues (rays, entries, hits, skip lists)", 2 * capacity * kQueueBytesPerRay});
  needs.push_back({"insert requests", request_bytes});
  return needs;
}

GpuPredictor::GpuPredictor(VulkanContext& ctx, const GpuBvh& bvh, const PredictorConfig& config)
    : s_(std::make_unique<State>()) {
  if (!ctx.info().int64 || !ctx.info().int64_atomics)
    throw Error(ctx.info().name + ": --hrpp on needs shaderInt64 and shaderBufferInt64Atomics");
  if (config.sample == 0) throw Error("HRPP: the adaptive predictor's sample stride must be >= 1");
  if (config.batch > HRPP_INSERT_BATCH_MAX)
    throw Error("batch: at most " + std::to_string(HRPP_INSERT_BATCH_MAX) + " rays");
  s_->ctx = &ctx;
  s_->config = config;
  // The node to insert for each triangle id: each go-up level applied once, here.
  const std::vector<std::uint32_t> leaves_of = leaf_of_prim(bvh);
  for (const GoUp& level : go_up_levels(config)) {
    // Padded to whole texels (4 ids each) for the texel view.
    std::vector<std::int32_t> node_of(node_of_prim_bytes(leaves_of.size()) / sizeof(std::int32_t),
                                      HRPP_EMPTY_NODE);
    for (std::size_t p = 0; p < leaves_of.size(); ++p)
      if (leaves_of[p] != kNoLeaf)
        node_of[p] = prediction_node(bvh, leaves_of[p], level.first, level.second);
    StorageBuffer b(ctx, node_of.size() * sizeof(std::int32_t), "node of triangle",
                    BufferBinding::kTexelOnly);
    b.upload(std::span<const std::int32_t>(node_of));
    TexelView view(ctx, b);
    s_->node_of_prim.push_back({level, std::move(b), std::move(view)});
  }
  for (RayClass c : kRayClasses) {
    if (!config.predicts(c)) continue;
    gpu::PredictorParams params = make_predictor_params(config, c, bvh.bounds);
    params.serial = config.serial ? 1u : 0u;
    s_->tables[c] = std::make_unique<Table>(ctx, params, c, config.fallback);
    s_->probing[c] = Probe::kAll;
  }
}

void GpuPredictor::connect(const DeviceBvh& device_bvh,
                           const std::function<QueueTraceKernel(QueryKind, bool)>& queue_kernel) {
  const bool skip_lists = s_->config.fallback == Fallback::kSkip;
  for (QueryKind kind : kQueryKinds)
    s_->queues[index_of(kind)] = std::make_unique<Queue>(*s_->ctx, queue_kernel(kind, skip_lists));
  for (RayClass c : kRayClasses) {
    if (!s_->tables[c]) continue;
    for (ComputePipeline* k : s_->tables[c]->stage_kernels()) {
      device_bvh.bind(*k);
      k->bind(HRPP_STAGE_BINDING_QUEUE, s_->queue(c).state);
      k->bind(HRPP_STAGE_BINDING_NODE_OF_PRIM, s_->node_of_prim_at(go_up_of(s_->config, c)));
    }
  }
}

GpuPredictor::~GpuPredictor() = default;
GpuPredictor::GpuPredictor(GpuPredictor&&) noexcept = default;
GpuPredictor& GpuPredictor::operator=(GpuPredictor&&) noexcept = default;

const PredictorConfig& GpuPredictor::config() const { return s_->config; }

void GpuPredictor::bind_rays(QueryKind kind, const TexelView& rays, const TexelView& hits,
                             std::size_t capacity) {
  Queue& q = s_->queue(kind);
  capacity = std::max<std::size_t>(capacity, 1);
  if (q.capacity < capacity) {
    q.ray_view = TexelView();
    q.entry_view = TexelView();
    q.hit_view = TexelView();
    q.skip_view = TexelView();
    q.rays = StorageBuffer();  // free first: one at a time in the heap
    q.entries = StorageBuffer();
    q.hits = StorageBuffer();
    q.skips = StorageBuffer();
    q.rays = StorageBuffer(*s_->ctx, capacity * sizeof(gpu::Ray), "HRPP queue rays");
    q.entries = StorageBuffer(*s_->ctx, capacity * sizeof(gpu::QueueEntry), "HRPP queue entries");
    q.hits = StorageBuffer(*s_->ctx, capacity * sizeof(gpu::Hit), "HRPP queue hits");
    q.skips = StorageBuffer(*s_->ctx, capacity * TexelView::kTexelBytes, "HRPP queue skip lists");
    q.ray_view = TexelView(*s_->ctx, q.rays);
    q.entry_view = TexelView(*s_->ctx, q.entries);
    q.hit_view = TexelView(*s_->ctx, q.hits);
    q.skip_view = TexelView(*s_->ctx, q.skips);
    q.capacity = capacity;
    q.trace.pipeline.bind(q.trace.rays, q.ray_view);
    q.trace.pipeline.bind(q.trace.hits, q.hit_view);
    if (q.trace.skips != QueueTraceKernel::kNoBinding)
      q.trace.pipeline.bind(q.trace.skips, q.skip_view);
  }
  for (RayClass c : kRayClasses) {
    if (query_kind(c) != kind || !s_->tables[c]) continue;
    Table& t = s_->table(c);
    const std::size_t request_bytes = capacity * sizeof(gpu::InsertRequest);
    if (t.requests.size() < request_bytes) {
      t.requests = StorageBuffer();
      t.requests = StorageBuffer(*s_->ctx, request_bytes, "insert requests");
      t.insert.bind(HRPP_TABLE_REQUESTS, t.requests);
      for (ComputePipeline* k : t.stage_kernels())
        k->bind(HRPP_STAGE_BINDING_TABLE + HRPP_TABLE_REQUESTS, t.requests);
    }
    for (ComputePipeline* k : t.stage_kernels()) {
      k->bind(HRPP_TRACE_BINDING_RAYS, rays);
      k->bind(HRPP_STAGE_BINDING_HITS, hits);
      k->bind(HRPP_STAGE_BINDING_QUEUE_RAYS, q.ray_view);
      k->bind(HRPP_STAGE_BINDING_QUEUE_ENTRIES, q.entry_view);
      k->bind(HRPP_STAGE_BINDING_QUEUE_HITS, q.hit_view);
      k->bind(HRPP_STAGE_BINDING_QUEUE_SKIPS, q.skip_view);
    }
  }
}

void GpuPredictor::set_probing(RayClass c, Probe mode, std::uint32_t sample_stride) {
  s_->probing[c] = s_->config.predicts(c) ? mode : Probe::kOff;
  s_->sample_stride[c] = sample_stride;
}

Probe GpuPredictor::probing(RayClass c) const { return s_->probing_now(c); }

bool GpuPredictor::records_indirect(RayClass c) const {
  return !(s_->batched() && probing(c) == Probe::kAll);
}

void GpuPredictor::begin(RayClass c) {
  if (probing(c) == Probe::kOff) return;
  const gpu::PredictorCounters zero{};
  s_->table(c).counters.upload(&zero, sizeof zero);
}

bool GpuPredictor::record_trace(VkCommandBuffer cmd, RayClass c, const RayCountSource& count,
                                const gpu::TracePushConstants& trace_pc, KernelTimer* timer) {
  const Probe mode = s_->recorded[c] = probing(c);
  if (mode == Probe::kSample) s_->record_sample(cmd, c, count, trace_pc, timer);
  if (mode != Probe::kAll) return false;
  if (!s_->batched()) {
    s_->record_rounds(cmd, c, count, trace_pc, timer);
  } else if (count.host) {
    s_->record_batches(cmd, c, *count.host, trace_pc);
  } else {
    throw Error("trace: HRPP's batched mode (batch) needs the ray count on the host");
  }
  return true;
}

Probe GpuPredictor::recorded(RayClass c) const { return s_->recorded[c]; }

void GpuPredictor::advance_clock(RayClass c, std::uint64_t rays) {
  s_->clock[c] += static_cast<std::uint32_t>(rays);
}

// The queue emptied for a trace of `count` rays, with their count copied in when it is on the
// device.
void GpuPredictor::State::start_queue(VkCommandBuffer cmd, RayClass c,
                                      const RayCountSource& count) {
  if (config.batch > 0)
    throw Error("HRPP's batched mode (batch) records with record_batches");
  Queue& q = queue(c);
  if (q.capacity == 0) throw Error("HRPP: a trace recorded before bind_rays sized its queue");
  upload_clock(c);
  const gpu::PredictQueue start = empty_queue(0, count.host ? *count.host : 0);
  const gpu::TraceCounters trace_start{};
  record_update(cmd, q.state, 0, sizeof start, &start);
  record_update(cmd, q.trace_counters, 0, sizeof trace_start, &trace_start);
  if (!count.host) {
    transfer_compute_barrier(cmd);  // the update before the copy into the same buffer
    record_copy(cmd, *count.buffer, count.count_offset, q.state,
                offsetof(gpu::PredictQueue, ray_count), sizeof(std::uint32_t));
  }
  transfer_compute_barrier(cmd);
}

void GpuPredictor::State::record_rounds(VkCommandBuffer cmd, RayClass c,
                                        const RayCountSource& count,
                                        const gpu::TracePushConstants& trace_pc,
                                        KernelTimer* timer) {
  start_queue(cmd, c, count);
  if (config.pilot < 2) return record_pass(cmd, c, count, trace_pc, HRPP_PASS_ALL, timer);
  record_pass(cmd, c, count, trace_pc, HRPP_PASS_PILOTS, timer);  // then the others
  restart_queue(cmd, c);
  record_pass(cmd, c, count, trace_pc, HRPP_PASS_OTHERS, timer);
}

void GpuPredictor::State::record_sample(VkCommandBuffer cmd, RayClass c,
                                        const RayCountSource& count,
                                        const gpu::TracePushConstants& trace_pc,
                                        KernelTimer* timer) {
  start_queue(cmd, c, count);
  record_pass(cmd, c, count, trace_pc, HRPP_PASS_SAMPLE, timer, stride_of(c), Phase::kSample);
  const gpu::StagePushConstants none = stage_push(trace_pc, HRPP_PASS_NONE);
  record_dispatch(cmd, table(c).predict(), &none, 1, timer,
                  TimerLabel{Kernel::hrpp_predict, Phase::kSampleEmpty, c});
}

void GpuPredictor::State::record_batches(VkCommandBuffer cmd, RayClass c, std::uint32_t count,
                                         const gpu::TracePushConstants& trace_pc) {
  Queue& q = queue(c);
  Table& t = table(c);
  upload_clock(c);
  const gpu::StagePushConstants spc = stage_push(trace_pc);  // no pilot: batch order
  const gpu::PredictQueue zero = empty_queue(0, 0);
  const gpu::TraceCounters trace_zero{};
  vkCmdUpdateBuffer(cmd, q.state.handle(), 0, sizeof zero, &zero);
  vkCmdUpdateBuffer(cmd, q.trace_counters.handle(), 0, sizeof trace_zero, &trace_zero);
  for (std::uint32_t first = 0; first < count; first += config.batch) {
    const std::uint32_t n = std::min(config.batch, count - first);
    // The batch: the cursor starts at `first`, prediction stops at first + n.
    restart_queue(cmd, c, std::pair{first, first + n});
    record_dispatch(cmd, t.predict(), &spc, (n + spc.trace_group_rays - 1) / spc.trace_group_rays,
                    nullptr);
    record_queue_trace(cmd, c, trace_pc, nullptr);
    const gpu::InsertPushConstants ipc{first, n, clock[c] + first, 0};
    record_dispatch(cmd, t.insert, &ipc, 1, nullptr);
  }
}

PredictedTrace GpuPredictor::finish(RayClass c) const {
  const bool sampled = s_->recorded[c] == Probe::kSample;
  const Queue& q = s_->queue(c);
  gpu::PredictQueue state{};
  q.state.download(&state, sizeof state);
  gpu::TraceCounters traced{};
  q.trace_counters.download(&traced, sizeof traced);
  PredictedTrace out;
  s_->table(c).counters.download(&out.predictor, sizeof out.predictor);
  const TraversalCounters queue_trace = traversal_counters(traced);
  out.queued = queue_trace.rays;
  const std::uint64_t answered = state.resolved + std::uint64_t{state.resolve_done};
  const std::uint32_t pass = sampled ? HRPP_PASS_SAMPLE : HRPP_PASS_ALL;
  if (answered != gpu::hrpp_pass_ray_count(state.ray_count, pass, s_->stride_of(c)) ||
      state.resolve_done != out.queued || state.aborted != 0 || traced.aborted != 0)
    throw Error(std::string("hrpp_predict / ") + q.trace.pipeline.name() + " / hrpp_resolve: only " +
                std::to_string(answered) + " of " + std::to_string(state.ray_count) +
                " rays answered (" + std::to_string(state.aborted + traced.aborted) +
                " cut short): the driver's loop limiter (lavapipe: 65,535 loop iterations per "
                "subgroup) ended the kernels' loops; lower rays_per_invocation");
  const auto& pc = out.predictor.c;
  out.counters.rays = answered;
  out.counters.hits = state.resolved + std::uint64_t{state.queue_hits};
  out.counters.interior_visited = queue_trace.interior_visited + pc[HRPP_PC_VERIFY_INTERIOR];
  out.counters.leaves_visited = queue_trace.leaves_visited + pc[HRPP_PC_VERIFY_LEAVES];
  out.counters.triangles_tested = queue_trace.triangles_tested + pc[HRPP_PC_VERIFY_TRIANGLES];
  return out;
}

std::uint32_t GpuPredictor::rays_per_workgroup(std::uint32_t rays_per_invocation) const {
  return s_->rays_per_workgroup(rays_per_invocation);
}

TableOccupancy GpuPredictor::occupancy(RayClass c) const {
  TableOccupancy o;
  if (!s_->tables[c]) return o;
  const Table& t = s_->table(c);
  o.capacity = std::uint64_t{gpu::hrpp_table_count(t.params.sm_tables)} * t.params.sets *
               t.params.ways;
  o.bytes = s_->config.table_bytes(c);
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
  for (RayClass c : kRayClasses) {
    if (!s_->tables[c]) continue;
    s_->table(c).params.count_baseline = on ? 1u : 0u;
    s_->table(c).upload_params();
  }
}

void GpuPredictor::clear() {
  for (RayClass c : kRayClasses) {
    if (s_->tables[c]) s_->table(c).clear();
    s_->clock[c] = 0;
  }
}

}  // namespace hrpp
