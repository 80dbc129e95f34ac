#include "vk/memory_ledger.h"

#include <algorithm>

namespace hrpp {

void MemoryLedger::add(const std::string& name, std::uint64_t bytes) {
  report_.buffers[name] += bytes;
  report_.total += bytes;
  report_.peak = std::max(report_.peak, report_.total);
}

void MemoryLedger::remove(const std::string& name, std::uint64_t bytes) {
  auto it = report_.buffers.find(name);
  if (it == report_.buffers.end()) return;
  it->second -= std::min(it->second, bytes);
  if (it->second == 0) report_.buffers.erase(it);
  report_.total -= std::min(report_.total, bytes);
}

}  // namespace hrpp
