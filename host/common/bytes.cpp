#include "common/bytes.h"

#include <cstdio>

namespace hrpp {

std::string format_bytes(std::uint64_t bytes) {
  constexpr std::uint64_t kKiB = 1024, kMiB = kKiB * 1024, kGiB = kMiB * 1024;
  const double b = static_cast<double>(bytes);
  char buf[40];
  if (bytes < kKiB)
    std::snprintf(buf, sizeof buf, "%llu bytes", static_cast<unsigned long long>(bytes));
  else if (bytes < kMiB)
    std::snprintf(buf, sizeof buf, "%.1f KiB", b / static_cast<double>(kKiB));
  else if (bytes < kGiB)
    std::snprintf(buf, sizeof buf, "%.2f MiB", b / static_cast<double>(kMiB));
  else
    std::snprintf(buf, sizeof buf, "%.2f GiB", b / static_cast<double>(kGiB));
  return buf;
}

}  // namespace hrpp
