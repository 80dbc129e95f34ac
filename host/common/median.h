// The median of a list of timings (the upper one of an even count; 0 for none): what the
// benchmarks report of their repeated runs.
#pragma once

#include <algorithm>
#include <vector>

namespace hrpp {

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace hrpp
