#include "hrpp/reference_table.h"

#include <algorithm>

#include "hrpp_table_set.h"

namespace hrpp {

namespace {
constexpr std::uint64_t kEmptyTag = ~std::uint64_t{0};
constexpr int kEmptyNode = HRPP_EMPTY_NODE;
}  // namespace

ReferenceTable::ReferenceTable(const gpu::PredictorParams& params)
    : params_(params),
      policy_(static_cast<TablePolicy>(params.policy)),
      ways_(std::size_t{params.sets} * params.ways) {
  for (Way& w : ways_) w.slots.assign(params.nodes, kEmptyNode);
}

// The GPU table's set function, shared with it.
std::size_t ReferenceTable::set_base(std::uint64_t key) const {
  return std::size_t{gpu::hrpp_set_of(key, params_.sets)} * params_.ways;
}

const std::vector<int>* ReferenceTable::lookup(std::uint64_t key, std::uint32_t clock) {
  if (ways_.empty()) return nullptr;
  const std::size_t base = set_base(key);
  for (std::uint32_t w = 0; w < params_.ways; ++w) {
    Way& way = ways_[base + w];
    if (way.tag != key) continue;
    if (policy_ == TablePolicy::kLru) way.stamp = std::max(way.stamp, clock);
    return &way.slots;
  }
  return nullptr;
}

// The way holding `key`, else the first empty way, else (lru, fifo) the way with the oldest
// stamp, emptied; none: dropped.
ReferenceTable::Way& ReferenceTable::claim_way(std::uint64_t key, Claim& claim,
                                               std::uint64_t& evictions) {
  const std::size_t base = set_base(key);
  for (std::uint32_t w = 0; w < params_.ways; ++w) {
    Way& way = ways_[base + w];
    if (way.tag == key || way.tag == kEmptyTag) {
      claim = way.tag == key ? Claim::kFound : Claim::kClaimed;
      way.tag = key;
      return way;
    }
  }
  Way* victim = &ways_[base];
  for (std::uint32_t w = 1; w < params_.ways; ++w)
    if (ways_[base + w].stamp < victim->stamp) victim = &ways_[base + w];
  switch (policy_) {
    case TablePolicy::kNone:
      claim = Claim::kDropped;
      return *victim;
    case TablePolicy::kLru:
    case TablePolicy::kFifo:
      break;
  }
  claim = Claim::kClaimed;
  ++evictions;
  victim->tag = key;
  std::fill(victim->slots.begin(), victim->slots.end(), kEmptyNode);
  return *victim;
}

ReferenceTable::Outcome ReferenceTable::insert(std::uint64_t key, int node, std::uint32_t clock,
                                               std::uint64_t& evictions) {
  if (ways_.empty()) return Outcome::kDropped;
  Claim claim = Claim::kFound;
  Way& way = claim_way(key, claim, evictions);
  if (claim == Claim::kDropped) return Outcome::kDropped;
  if (policy_ == TablePolicy::kLru || (policy_ == TablePolicy::kFifo && claim == Claim::kClaimed))
    way.stamp = std::max(way.stamp, clock);
  Outcome outcome = Outcome::kDropped;
  for (int& slot : way.slots) {
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
  if (outcome == Outcome::kDropped && policy_ != TablePolicy::kNone) {
    way.slots[clock % params_.nodes] = node;
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
  std::uint64_t n = 0;
  for (const Way& w : ways_)
    n += static_cast<std::uint64_t>(std::count_if(w.slots.begin(), w.slots.end(),
                                                  [](int s) { return s != kEmptyNode; }));
  return n;
}

}  // namespace hrpp
