#include "common/peak_rss.h"

#include <sys/resource.h>

namespace hrpp {

std::uint64_t peak_rss_bytes() {
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
  return static_cast<std::uint64_t>(u.ru_maxrss) * 1024;  // Linux: kilobytes
}

}  // namespace hrpp
