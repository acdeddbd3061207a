#pragma once
// The median the benchmarks quote (the upper one of an even count); -1 for no samples.
#include <algorithm>
#include <vector>

namespace incise::bench {

inline double median(std::vector<double> v) {
  if (v.empty()) return -1;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace incise::bench
