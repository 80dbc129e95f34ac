// What a predicted trace did, in the paper's terms: rates, skipped interior nodes, savings %
// (and net of the verification work), table occupancy and bytes. Computed from the counters of
// one ray class (shaders/shared/hrpp_types.h, HRPP_PC_*) and the trace counters of the same run.
#pragma once

#include <cstdint>
#include <string>

#include "hrpp/predictor_config.h"
#include "trace/query_kind.h"
#include "trace/traversal_counters.h"

namespace hrpp {

// What a table holds after a trace (GpuPredictor::occupancy).
struct TableOccupancy {
  std::uint64_t entries = 0;   // tags in use
  std::uint64_t nodes = 0;     // node slots in use
  std::uint64_t capacity = 0;  // sets × ways
  std::uint64_t bytes = 0;     // the table's GPU memory (TableConfig::bytes)

  TableOccupancy& operator+=(const TableOccupancy& o) {
    entries += o.entries;
    nodes += o.nodes;
    capacity += o.capacity;
    bytes += o.bytes;
    return *this;
  }
};

// The predictor counters' JSON keys by index: HRPP_PREDICTOR_COUNTERS, the one list.
struct CounterKey {
  std::uint32_t index;  // HRPP_PC_*
  const char* key;
};
inline constexpr CounterKey kPredictorCounterKeys[] = {
#define HRPP_COUNTER_KEY(NAME, key, index) {index, #key},
    HRPP_PREDICTOR_COUNTERS(HRPP_COUNTER_KEY)
#undef HRPP_COUNTER_KEY
};

// The list's indices are 0, 1, 2, ... in list order and fit the counters block.
constexpr bool counter_indices_in_order() {
  std::uint32_t next = 0;
  for (const CounterKey& k : kPredictorCounterKeys)
    if (k.index != next++) return false;
  return next <= HRPP_PC_COUNT;
}
static_assert(counter_indices_in_order());

// Counters that only a count_baseline run fills.
constexpr bool is_baseline_counter(std::uint32_t index) {
  return index == HRPP_PC_BASELINE_INTERIOR || index == HRPP_PC_BASELINE_LEAVES ||
         index == HRPP_PC_BASELINE_TRIANGLES || index == HRPP_PC_WRONG_CLOSEST;
}

struct PredictorSummary {
  gpu::PredictorCounters counters{};
  TraversalCounters trace;    // the predicted run's work, verification included
  TableOccupancy occupancy;
  bool baseline = false;      // counters hold HRPP_PC_BASELINE_INTERIOR (count_baseline run)
  double hit_rate = 0.0;      // predictor hits / probes
  double tp_rate = 0.0;       // true positives / predictor hits
  double fp_rate = 0.0;       // false positives / predictor hits
  // Interior nodes a full traversal would have visited (baseline) minus those visited by the
  // traversals from the root that did run; savings = skipped / baseline; net: minus the
  // interior nodes spent verifying predictions too.
  std::int64_t skipped_interior = 0;
  double savings = 0.0;
  double net_savings = 0.0;
};

PredictorSummary summarize(const gpu::PredictorCounters& counters, const TraversalCounters& trace,
                           const TableOccupancy& occupancy, bool baseline);

// One line of configuration: "hash hrpp N=6, go-up 0, speculative, table 1024x8x8 lru (352 KiB)".
std::string describe(const PredictorConfig& config);

// Lines for the terminal, each starting with `label` padded to 12 columns.
std::string format_summary(const std::string& label, const PredictorSummary& s, QueryKind kind);

}  // namespace hrpp
