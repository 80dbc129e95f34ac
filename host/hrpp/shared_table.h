// One class's predictor table shared by the threads of HRPP inline on the CPU
// (host/hrpp/inline_predictor.h): the reference table (host/hrpp/reference_table.h) behind
// striped locks, one per group of sets, and a use clock every thread draws its rays' stamps
// from. A lookup copies the entry's nodes out under its stripe's lock, so another thread's
// insert cannot change them while they are verified.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

#include "hrpp/predictor_config.h"
#include "hrpp/reference_table.h"

namespace hrpp {

class SharedTable {
 public:
  using Nodes = std::array<int, kMaxTableNodes>;

  explicit SharedTable(const gpu::PredictorParams& params);

  // The entry's node slots copied into `out`: their count, 0 when no way holds the key; its
  // nearest-hit word into `nearest` (ReferenceTable::lookup).
  std::size_t lookup(std::uint64_t key, std::uint32_t clock, Nodes& out, std::uint32_t& nearest);
  ReferenceTable::Outcome insert(std::uint64_t key, int node, float t, std::uint32_t clock,
                                 std::uint64_t& evictions);
  // Stamps for `rays` more rays: the first of them (the threads' rays share one clock).
  std::uint32_t draw_clock(std::uint32_t rays) { return clock_.fetch_add(rays); }

 private:
  std::mutex& stripe(std::uint64_t key) { return stripes_[table_.set_of(key) % stripes_.size()]; }

  ReferenceTable table_;
  std::vector<std::mutex> stripes_;
  std::atomic<std::uint32_t> clock_{0};
};

}  // namespace hrpp
