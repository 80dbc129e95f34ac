// The CPU mirror of one class's GPU predictor table (shaders/lib/hrpp_table.glsl): sets × ways
// entries of a 64-bit tag (the full key), a use stamp and `nodes` node slots, the same set
// function, and the same policies when an insert finds no room (none: drop; lru: evict the way
// with the oldest stamp, or overwrite slot clock mod nodes of a full node list; fifo: as lru,
// with a way's stamp set only when its key comes in), and with the distance gate the nearest hit
// per entry. Applied one
// operation at a time in the deterministic order (hrpp_insert's), it holds exactly what the GPU
// table holds, so the reference predictor is the ground truth of every policy.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "gpu_types.h"
#include "hrpp/predictor_config.h"
#include "hrpp_types.h"

namespace hrpp {

class ReferenceTable {
 public:
  enum class Outcome { kInserted, kPresent, kDropped };

  ReferenceTable() = default;  // no sets: holds nothing
  explicit ReferenceTable(const gpu::PredictorParams& params);

  // The node slots of `key`'s entry (filled in slot order; HRPP_EMPTY_NODE after the last
  // node), or an empty span when no way holds the key. A hit renews the entry's stamp with
  // `clock` (lru only) and sets `nearest` to the entry's nearest-hit word (the distance gate's,
  // shaders/shared/hrpp_distance_gate.h; 0: none yet).
  std::span<const int> lookup(std::uint64_t key, std::uint32_t clock, std::uint32_t& nearest);
  // Inserts `node`, found by a traced ray at `t`, under `key` at use stamp `clock`; adds the
  // entries and nodes it replaced to `evictions`.
  Outcome insert(std::uint64_t key, int node, float t, std::uint32_t clock,
                 std::uint64_t& evictions);

  // The set `key` maps to (the GPU table's set function).
  std::size_t set_of(std::uint64_t key) const { return set_base(key) / params_.ways; }

  std::uint64_t entries() const;       // ways holding a key
  std::uint64_t stored_nodes() const;  // occupied slots

 private:
  struct Way {
    std::uint64_t tag = ~std::uint64_t{0};  // empty
    std::uint32_t stamp = 0;
    std::uint32_t nearest = 0;  // the distance gate's nearest-hit word (0: none yet)
  };
  std::size_t set_base(std::uint64_t key) const;
  // What claim_way did: found the key's way, brought the key in (an empty way or a victim), or
  // dropped the insert (none).
  enum class Claim { kFound, kClaimed, kDropped };
  // Way `w`'s claim; its node slots (HRPP_EMPTY_NODE = empty), one array for every way.
  std::size_t claim_way(std::uint64_t key, Claim& claim, std::uint64_t& evictions);
  std::span<int> slots(std::size_t w) { return {slots_.data() + w * params_.nodes, params_.nodes}; }

  gpu::PredictorParams params_{};
  TablePolicy policy_;
  std::vector<Way> ways_;
  std::vector<int> slots_;  // ways × nodes
};

}  // namespace hrpp
