#include "hrpp/shared_table.h"

#include <algorithm>

namespace hrpp {

namespace {
constexpr std::size_t kStripes = 1024;
}  // namespace

SharedTable::SharedTable(const gpu::PredictorParams& params)
    : table_(params), stripes_(std::min<std::size_t>(kStripes, std::max(params.sets, 1u))) {}

std::size_t SharedTable::lookup(std::uint64_t key, std::uint32_t clock, Nodes& out,
                                std::uint32_t& nearest) {
  const std::lock_guard lock(stripe(key));
  const std::span<const int> slots = table_.lookup(key, clock, nearest);
  std::copy(slots.begin(), slots.end(), out.begin());
  return slots.size();
}

ReferenceTable::Outcome SharedTable::insert(std::uint64_t key, int node, float t,
                                            std::uint32_t clock, std::uint64_t& evictions) {
  const std::lock_guard lock(stripe(key));
  return table_.insert(key, node, t, clock, evictions);
}

}  // namespace hrpp
