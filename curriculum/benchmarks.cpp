#include "curriculum/benchmarks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace incise::curriculum {

double percentile(std::span<const double> sorted, double p) {
  if (sorted.empty()) throw std::invalid_argument("percentile of no values");
  if (!(p >= 0 && p <= 1)) throw std::invalid_argument("percentile must be within [0, 1]");
  const double rank = p * static_cast<double>(sorted.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(rank));
  const auto above = std::min(below + 1, sorted.size() - 1);
  const double f = rank - static_cast<double>(below);
  return sorted[below] + f * (sorted[above] - sorted[below]);
}

BenchmarkStats summarize(std::span<const double> values) {
  if (values.empty()) throw std::invalid_argument("a benchmark needs at least one expert run");
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw std::invalid_argument("expert value " + std::to_string(i) + " is not finite");
    }
  }
  std::vector<double> sorted(values.begin(), values.end());
  std::sort(sorted.begin(), sorted.end());
  BenchmarkStats stats;
  stats.n = static_cast<int>(sorted.size());
  double sum = 0;
  for (const double v : sorted)
    sum += v;
  stats.mean = sum / stats.n;
  // Two passes: the sum of squared deviations stays accurate when the values sit far from 0.
  double squares = 0;
  for (const double v : sorted)
    squares += (v - stats.mean) * (v - stats.mean);
  stats.sd = stats.n > 1 ? std::sqrt(squares / (stats.n - 1)) : 0.0;
  stats.median = percentile(sorted, 0.5);
  stats.p10 = percentile(sorted, 0.1);
  stats.p90 = percentile(sorted, 0.9);
  return stats;
}

double relative_score(double value, const BenchmarkStats& stats) {
  if (stats.n < 2 || !(stats.sd > 0)) return std::numeric_limits<double>::quiet_NaN();
  return (value - stats.mean) / stats.sd;
}

std::map<std::pair<std::string, std::string>, Benchmark> group_benchmarks(
    std::span<const ExpertScore> scores) {
  std::map<std::pair<std::string, std::string>, std::pair<std::string, std::vector<double>>> groups;
  for (const ExpertScore& s : scores) {
    if (!std::isfinite(s.value)) continue;
    auto& [unit, values] = groups[{s.task, s.metric}];
    if (values.empty()) unit = s.unit;
    values.push_back(s.value);
  }
  std::map<std::pair<std::string, std::string>, Benchmark> out;
  for (const auto& [key, group] : groups)
    out[key] = {group.first, summarize(group.second)};
  return out;
}

}  // namespace incise::curriculum
