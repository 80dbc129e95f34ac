// The device memory a VulkanContext's buffers hold, by buffer name: every StorageBuffer adds its
// allocation when made and takes it off when freed. The render stats' "memory" object and the
// render command's memory line are read from it.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>

namespace hrpp {

// The memory type buffers of one role get (vk/memory_placement.h), for the reports.
struct MemoryTypeReport {
  std::uint32_t type = 0;  // Vulkan memory type index
  std::uint32_t heap = 0;  // its heap
  std::string flags;       // memory_flags_text
  bool mapped = false;     // mapped (else staged through the staging buffer)
};

// The context's memory mode and where each role's buffers live.
struct MemoryPlacement {
  std::string mode;                               // "staged" or "mapped"
  std::map<std::string, MemoryTypeReport> roles;  // by kMemoryRoleNames
};

struct MemoryReport {
  std::map<std::string, std::uint64_t> buffers;  // bytes allocated now, summed per name
  std::uint64_t total = 0;                       // bytes allocated now
  std::uint64_t peak = 0;                        // the most allocated at once so far
  std::uint64_t heap = 0;                        // the device's heap (or budget), for reference
  MemoryPlacement placement;
};

class MemoryLedger {
 public:
  void add(const std::string& name, std::uint64_t bytes);
  void remove(const std::string& name, std::uint64_t bytes);
  MemoryReport report() const { return report_; }
  std::uint64_t total() const { return report_.total; }
  void set_heap(std::uint64_t bytes) { report_.heap = bytes; }
  void set_placement(MemoryPlacement placement) { report_.placement = std::move(placement); }

 private:
  MemoryReport report_;
};

}  // namespace hrpp
