// How HRPP runs: hash, mode, go-up level, table geometry and policy, insert order. Filled by the
// CLI (host/app/hrpp_options.h), read by the GPU predictor (host/front/gpu_predictor.h) and the CPU
// reference predictor (host/hrpp/reference_predictor.h).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "bvh/aabb.h"
#include "common/name_table.h"
#include "trace/ray_class.h"
#include "hrpp/ray_hash.h"
#include "hrpp_types.h"

namespace hrpp {

static_assert(sizeof(gpu::PredictorParams) == 128);
static_assert(sizeof(gpu::InsertRequest) == 16);
static_assert(sizeof(gpu::PredictorCounters) == 8 * HRPP_PC_COUNT);

enum class PredictorMode : std::uint32_t {
  kSpeculative = HRPP_MODE_SPECULATIVE,
  kExact = HRPP_MODE_EXACT,
};

enum class TablePolicy : std::uint32_t {
  kNone = HRPP_POLICY_NONE,
  kLru = HRPP_POLICY_LRU,
  kFifo = HRPP_POLICY_FIFO,
  kMicro21 = HRPP_POLICY_MICRO21,
};

inline constexpr NameTable<PredictorMode, 2> kPredictorModeNames = {
    {{PredictorMode::kSpeculative, "speculative"}, {PredictorMode::kExact, "exact"}}};
inline constexpr NameTable<TablePolicy, HRPP_POLICY_COUNT> kTablePolicyNames = {
    {{TablePolicy::kNone, "none"},
     {TablePolicy::kLru, "lru"},
     {TablePolicy::kFifo, "fifo"},
     {TablePolicy::kMicro21, "micro21"}}};
constexpr const char* predictor_mode_name(PredictorMode m) {
  return name_in(kPredictorModeNames, m);
}
constexpr const char* table_policy_name(TablePolicy p) { return name_in(kTablePolicyNames, p); }

// What a ray traces when its prediction did not answer it (false positives and negatives; in
// exact mode also true positives of hit-all rays, bounded by the predicted t): a traversal from
// the root, as in the paper (root), or one from the root that does not enter the first
// HRPP_SKIP_NODES nodes its verification tested (skip): nothing in them answers the ray, so the
// answer is the same and a false positive's verification is not paid twice.
enum class Fallback : std::uint8_t { kRoot, kSkip };
inline constexpr NameTable<Fallback, 2> kFallbackNames = {
    {{Fallback::kRoot, "root"}, {Fallback::kSkip, "skip"}}};
constexpr const char* fallback_name(Fallback f) { return name_in(kFallbackNames, f); }

// Most node slots per entry (table_nodes), most per-SM tables (sm_tables).
inline constexpr std::uint32_t kMaxTableNodes = 64;
inline constexpr std::uint32_t kMaxSmTables = 256;

// Capacity = sets × ways entries of `nodes` node slots each, in each of sm_tables tables (per-SM
// tables: shaders/shared/hrpp_table_set.h).
struct TableConfig {
  std::uint32_t sets = 1u << 12;
  std::uint32_t ways = 8;
  std::uint32_t nodes = 8;
  TablePolicy policy = TablePolicy::kLru;
  std::uint32_t sm_tables = 1;

  std::uint64_t entries() const { return std::uint64_t{sets} * ways * sm_tables; }
  friend bool operator==(const TableConfig&, const TableConfig&) = default;
  // Bytes on the GPU: per entry a 64-bit tag, a 32-bit use stamp and 32-bit node slots; with
  // the distance gate also a 32-bit nearest hit.
  std::uint64_t bytes(bool gate = false) const {
    return entries() * (8u + 4u + (gate ? 4u : 0u) + 4u * std::uint64_t{nodes});
  }
};

// Named table sizes (--table-preset, per ray class); "tuned" (512 KiB) is the default of camera
// and bounce rays, "beam" (4096x2x4 lru, 224 KiB: four occluder subtrees per light-space key)
// the shadow rays'. "unbounded": the
// paper's limit study (policy none, so nothing is ever evicted; inserts that find no room are
// counted as drops: 3 of 294k on the bunny's 1024×1024 primaries, where a few keys gather more
// than 16 leaves). "small": 352 KiB. "tiny": 8 entries, for tests of eviction. "micro21":
// MICRO'21's published tables (its MOBILE configuration as submitted: 2 SMs, each with 1024
// entries, 4-way set-associative, 1 node an entry; policy micro21): 16 KiB a table here.
enum class TablePreset : std::uint8_t { kTuned, kBeam, kSmall, kUnbounded, kTiny, kMicro21 };
inline constexpr NameTable<TablePreset, 6> kTablePresetNames = {
    {{TablePreset::kTuned, "tuned"},
     {TablePreset::kBeam, "beam"},
     {TablePreset::kSmall, "small"},
     {TablePreset::kUnbounded, "unbounded"},
     {TablePreset::kTiny, "tiny"},
     {TablePreset::kMicro21, "micro21"}}};
TableConfig table_preset(TablePreset preset);
// The same by name; throws hrpp::Error naming --table-preset for an unknown one.
TableConfig table_preset(std::string_view name);

struct PredictorConfig {
  bool enabled = false;
  // Per ray class: its key (the settings file's hash, hash_bits) and the go-up level of what its
  // table stores (go_up). The defaults here are the paper's (hrpp at N = 6, leaves); the CLI's
  // --hrpp on default is host/app/hrpp_options.h's.
  PerClass<HashConfig> hash;
  PredictorMode mode = PredictorMode::kSpeculative;
  Fallback fallback = Fallback::kSkip;
  PerClass<std::uint32_t> go_up{};
  PerClass<float> go_up_size{};  // go_up_size: then up to a box of this share of the scene's
  PerClass<TableConfig> table;   // per ray class (--table-preset, table_*)
  // The distance gate per hit-all class (gate; shaders/shared/hrpp_distance_gate.h):
  // speculative mode accepts a true positive only within gate × the nearest hit its key's traced
  // rays found, and bounds an exact trace with the others. 0: off.
  PerClass<float> gate{};
  // Insert order. 0: inserts happen during the trace, as rays finish (fast, not reproducible).
  // K > 0, the deterministic order: rays go in batches of K in index order; every ray of a batch
  // probes the table as the previous batches left it; after the batch its inserts are applied
  // in ray-index order. With `serial` (one ray per subgroup, so the GPU visits nodes in the CPU
  // reference's order), the CPU reference predictor (host/hrpp/reference_predictor.h, whose
  // table mirrors the GPU's policy) reproduces every GPU counter.
  std::uint32_t batch = 0;
  bool serial = false;
  // Count what a full traversal of every probed ray visits (savings %, wrong closest hits):
  // doubles the traversal work, so timings are taken with it off.
  bool count_baseline = false;
  // The pilot schedule (pilot K): a trace first predicts and traces every K-th ray and
  // inserts their hits, then predicts the others, which find the pilots' entries (a wavefront
  // probes all at once: without it, rays of one trace never see each other's inserts). 0 or 1:
  // one round. Not with batches (their order is the deterministic one).
  std::uint32_t pilot = 16;
  // Ray classes that predict (--hrpp-rays); the others trace as with HRPP off.
  PerClass<bool> classes{{true, true, true}};
  // Per frame, per class: stop probing a class whose prediction costs more time than it saves,
  // and try it again now and then (host/hrpp/adaptive_predictor.h). Off: every enabled class
  // probes every ray (the limit study's counting runs).
  bool adaptive = true;
  // The adaptive predictor's sample frames: every `sample`-th block of HRPP_SAMPLE_BLOCK
  // consecutive rays of the class runs the HRPP stage, then the plain trace traces every ray
  // (>= 1; 1 samples every ray). The first sample's stride, and the least the adaptive predictor
  // derives from a sample's cost: a sample whose rays cost twice a plain trace's (lavapipe:
  // predict, the queue's trace and resolve) stays within the 2% budget at 1/100 of the rays.
  std::uint32_t sample = 128;

  bool predicts(RayClass c) const { return enabled && classes[c]; }
  std::uint64_t table_bytes(RayClass c) const { return table[c].bytes(gate[c] > 0.0f); }
  // The same key or go-up level for every class.
  void set_hash(const HashConfig& h) { hash = {{h, h, h}}; }
  void set_go_up(std::uint32_t level) { go_up = {{level, level, level}}; }
  void set_table(const TableConfig& t) { table = {{t, t, t}}; }
  // Whether class c's table may hold interior nodes (subtrees to verify).
  bool stores_subtrees(RayClass c) const { return go_up[c] > 0 || go_up_size[c] > 0.0f; }
  // Whether the adaptive predictor decides per frame: batches (the deterministic order, for
  // reproducible counts) cannot sample, so with them every enabled class probes every ray.
  bool adapts() const { return adaptive && batch == 0; }
};

// One per-class setting as the --stats summaries write it: "v" when every predicting class has the same value
// (camera's when none predicts), else "class=v,..." over the predicting classes in class order.
template <class T, class Text>
std::string per_class_text(const PredictorConfig& config, const PerClass<T>& values, Text text) {
  std::string list;
  bool uniform = true;
  const T* first = nullptr;
  for (RayClass c : kRayClasses) {
    if (!config.predicts(c)) continue;
    if (first && !(values[c] == *first)) uniform = false;
    if (!first) first = &values[c];
    list += (list.empty() ? "" : ",") + std::string(ray_class_name(c)) + "=" + text(values[c]);
  }
  if (!first) return text(values[RayClass::kCamera]);
  return uniform ? text(*first) : list;
}

// The kernels' parameters of class c's predictor. Throws hrpp::Error for a table whose sets is
// not a power of two or whose sizes are 0, or a bad hash precision or go-up level.
gpu::PredictorParams make_predictor_params(const PredictorConfig& config, RayClass c,
                                           const Aabb& scene_box);

}  // namespace hrpp
