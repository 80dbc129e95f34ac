#include "hrpp/reference_table.h"

#include <algorithm>

#include "hrpp_distance_gate.h"
#include "hrpp_table_set.h"

namespace hrpp {

namespace {
constexpr std::uint64_t kEmptyTag = ~std::uint64_t{0};
constexpr int kEmptyNode = HRPP_EMPTY_NODE;
}  // namespace

ReferenceTable::ReferenceTable(const gpu::PredictorParams& params)
    : params_(params),
      policy_(static_cast<TablePolicy>(params.policy)),
      ways_(std::size_t{gpu::hrpp_table_count(params.sm_tables)} * params.sets * params.ways),
      slots_(ways_.size() * params.nodes, kEmptyNode) {}

// The GPU table's set function, shared with it.
std::size_t ReferenceTable::set_base(std::uint64_t key) const {
  return gpu::hrpp_entry_base(key, params_.sets, params_.ways, params_.policy);
}

std::span<const int> ReferenceTable::lookup(std::uint64_t key, std::uint32_t clock,
                                            std::uint32_t& nearest) {
  nearest = 0;
  if (ways_.empty()) return {};
  const std::size_t base = set_base(key);
  for (std::uint32_t w = 0; w < params_.ways; ++w) {
    Way& way = ways_[base + w];
    if (way.tag != key) continue;
    if (gpu::hrpp_renews_stamps(params_.policy)) way.stamp = std::max(way.stamp, clock);
    nearest = way.nearest;
    return slots(base + w);
  }
  return {};
}

// The way holding `key`, else the first empty way, else (lru, fifo, micro21) the way with the
// oldest stamp, emptied; none: dropped.
std::size_t ReferenceTable::claim_way(std::uint64_t key, Claim& claim,
                                      std::uint64_t& evictions) {
  const std::size_t base = set_base(key);
  for (std::uint32_t w = 0; w < params_.ways; ++w) {
    Way& way = ways_[base + w];
    if (way.tag == key || way.tag == kEmptyTag) {
      claim = way.tag == key ? Claim::kFound : Claim::kClaimed;
      if (claim == Claim::kClaimed) way.nearest = 0;
      way.tag = key;
      return base + w;
    }
  }
  std::size_t victim = base;
  for (std::uint32_t w = 1; w < params_.ways; ++w)
    if (ways_[base + w].stamp < ways_[victim].stamp) victim = base + w;
  switch (policy_) {
    case TablePolicy::kNone:
      claim = Claim::kDropped;
      return victim;
    case TablePolicy::kLru:
    case TablePolicy::kFifo:
    case TablePolicy::kMicro21:
      break;
  }
  claim = Claim::kClaimed;
  ++evictions;
  ways_[victim].tag = key;
  ways_[victim].nearest = 0;
  std::ranges::fill(slots(victim), kEmptyNode);
  return victim;
}

ReferenceTable::Outcome ReferenceTable::insert(std::uint64_t key, int node, float t,
                                               std::uint32_t clock, std::uint64_t& evictions) {
  if (ways_.empty()) return Outcome::kDropped;
  Claim claim = Claim::kFound;
  const std::size_t w = claim_way(key, claim, evictions);
  if (claim == Claim::kDropped) return Outcome::kDropped;
  Way& way = ways_[w];
  if (gpu::hrpp_renews_stamps(params_.policy) ||
      (policy_ == TablePolicy::kFifo && claim == Claim::kClaimed))
    way.stamp = std::max(way.stamp, clock);
  if (params_.gate > 0.0f) way.nearest = std::max(way.nearest, gpu::hrpp_nearest_word(t));
  Outcome outcome = Outcome::kDropped;
  const std::span<int> way_slots = slots(w);
  for (int& slot : way_slots) {
    if (slot == node) {
      outcome = Outcome::kPresent;
      break;
    }
    if (slot == kEmptyNode) {
      slot = node;
      outcome = Outcome::kInserted;
      break;
    }
  }
  if (outcome == Outcome::kDropped && gpu::hrpp_replaces_nodes(params_.policy)) {
    way_slots[clock % params_.nodes] = node;
    ++evictions;
    outcome = Outcome::kInserted;
  }
  return outcome;
}

std::uint64_t ReferenceTable::entries() const {
  return static_cast<std::uint64_t>(
      std::count_if(ways_.begin(), ways_.end(), [](const Way& w) { return w.tag != kEmptyTag; }));
}

std::uint64_t ReferenceTable::stored_nodes() const {
  return static_cast<std::uint64_t>(
      std::ranges::count_if(slots_, [](int s) { return s != kEmptyNode; }));
}

}  // namespace hrpp
