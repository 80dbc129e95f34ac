// The device memory a VulkanContext's buffers hold, by buffer name: every StorageBuffer adds its
// allocation when made and takes it off when freed. The render stats' "memory" object and the
// render command's memory line are read from it.
#pragma once

#include <cstdint>
#include <map>
#include <string>

namespace hrpp {

struct MemoryReport {
  std::map<std::string, std::uint64_t> buffers;  // bytes allocated now, summed per name
  std::uint64_t total = 0;                       // bytes allocated now
  std::uint64_t peak = 0;                        // the most allocated at once so far
  std::uint64_t heap = 0;                        // the device's heap (or budget), for reference
};

class MemoryLedger {
 public:
  void add(const std::string& name, std::uint64_t bytes);
  void remove(const std::string& name, std::uint64_t bytes);
  MemoryReport report() const { return report_; }
  std::uint64_t total() const { return report_.total; }
  void set_heap(std::uint64_t bytes) { report_.heap = bytes; }

 private:
  MemoryReport report_;
};

}  // namespace hrpp
