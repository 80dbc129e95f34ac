#include "harness/time_tracer.h"

#include <algorithm>
#include <fstream>

#include "common/median.h"

namespace hrpp {

TracerResult time_tracer(Tracer& tracer, std::span<const gpu::Ray> rays, QueryKind kind, int repeat,
                         std::vector<gpu::Hit>& hits) {
  TracerResult r;
  r.kind = tracer.kind();
  r.name = tracer.name();
  r.timing = tracer.timing();
  tracer.trace(rays.first(std::min<std::size_t>(rays.size(), 65536)), kind);
  for (int i = 0; i < repeat; ++i) {
    TracerRun run = tracer.trace(rays, kind);
    r.ms.push_back(run.ms);
    hits = std::move(run.hits);
    r.counters = run.counters;
    r.predictor = run.predictor;
  }
  r.median_ms = median(r.ms);
  r.mrays = r.median_ms > 0.0 ? static_cast<double>(rays.size()) / (r.median_ms * 1e3) : 0.0;
  r.hits = static_cast<std::size_t>(
      std::count_if(hits.begin(), hits.end(), [](const gpu::Hit& h) { return h.prim >= 0; }));
  return r;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) {
        std::size_t b = line.find_first_not_of(" \t", colon + 1);
        return b == std::string::npos ? "unknown" : line.substr(b);
      }
    }
  }
  return "unknown";
}

}  // namespace hrpp
