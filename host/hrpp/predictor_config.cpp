#include "hrpp/predictor_config.h"

#include <bit>
#include <cmath>
#include <string>

#include "common/error.h"

namespace hrpp {

TableConfig table_preset(TablePreset preset) {
  // unbounded: 2^17 sets × 16 ways × 16 nodes = 2M entries, 152 MiB (the node slots exactly fill
  // lavapipe's 128 MiB storage-buffer range); 16 ways keep sets from overflowing (with 8 ways
  // a few inserts of 1M-ray batches were dropped). small: 2^10 × 8 × 8 = 8k entries, 352 KiB.
  // tuned (the default): 2^14 × 2 × 1 = 32k entries of one node, 512 KiB: the cheapest probe
  // measured (2 tag fetches, one leaf to verify) for the most true positives per byte.
  switch (preset) {
    case TablePreset::kUnbounded:
      return {1u << 17, 16, 16, TablePolicy::kNone};
    case TablePreset::kSmall:
      return {1u << 10, 8, 8, TablePolicy::kLru};
    case TablePreset::kTiny:
      return {4, 2, 2, TablePolicy::kLru};
    case TablePreset::kBeam:
      return {1u << 12, 2, 4, TablePolicy::kLru};
    case TablePreset::kMicro21:
      return {1u << 8, 4, 1, TablePolicy::kMicro21, 2};
    case TablePreset::kTuned:
      break;
  }
  return {1u << 14, 2, 1, TablePolicy::kLru};
}

TableConfig table_preset(std::string_view name) {
  return table_preset(parse_in(kTablePresetNames, name, "--table-preset: unknown preset"));
}

gpu::PredictorParams make_predictor_params(const PredictorConfig& config, RayClass c,
                                           const Aabb& scene_box) {
  const TableConfig& t = config.table[c];
  if (t.sets == 0 || !std::has_single_bit(t.sets))
    throw Error("table_sets: " + std::to_string(t.sets) + " is not a power of two");
  if (t.ways == 0 || t.ways > 64) throw Error("table_ways: must be 1..64");
  if (t.sm_tables == 0 || t.sm_tables > kMaxSmTables)
    throw Error("sm_tables: must be 1.." + std::to_string(kMaxSmTables));
  if (t.nodes == 0 || t.nodes > kMaxTableNodes)
    throw Error("table_nodes: must be 1.." + std::to_string(kMaxTableNodes));
  if (config.go_up[c] > 64) throw Error("go_up: must be 0..64");
  if (!(config.go_up_size[c] >= 0.0f && config.go_up_size[c] <= 1.0f))
    throw Error("go_up_size: must be 0..1");
  if (!(config.gate[c] >= 0.0f && std::isfinite(config.gate[c])))
    throw Error("gate: must be a finite number >= 0");
  gpu::PredictorParams p{};
  p.hash = make_hash_params(config.hash[c], scene_box);
  p.sets = t.sets;
  p.ways = t.ways;
  p.nodes = t.nodes;
  p.policy = static_cast<std::uint32_t>(t.policy);
  p.sm_tables = t.sm_tables;
  p.go_up = config.go_up[c];
  p.go_up_size = config.go_up_size[c];
  p.gate = config.gate[c];
  p.mode = static_cast<std::uint32_t>(config.mode);
  p.insert_deferred = config.batch > 0 ? 1u : 0u;
  p.count_baseline = config.count_baseline ? 1u : 0u;
  return p;
}

}  // namespace hrpp
