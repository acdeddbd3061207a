#pragma once
// Expert benchmarks: a task's metric summarised over its recorded expert runs,
// and an attempt's value relative to it, so that a trainee sees not only "passed" but how far from
// an expert they are.
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace incise::curriculum {

struct BenchmarkStats {
  int n = 0;  // expert runs
  double mean = 0;
  double sd = 0;      // sample standard deviation (n - 1); 0 for a single run
  double median = 0;  // linear interpolation between order statistics
  double p10 = 0;     // 10th and 90th percentiles, likewise
  double p90 = 0;
};

// The statistics of #values (any order). Throws std::invalid_argument for no values or a
// non-finite one.
BenchmarkStats summarize(std::span<const double> values);

// The percentile p in [0, 1] of sorted values: the order statistic at rank p (n - 1), linearly
// interpolated. Throws std::invalid_argument for no values or p outside [0, 1].
double percentile(std::span<const double> sorted, double p);

// (value - mean) / sd: how many expert SDs an attempt is from the experts' mean. NaN when there
// are fewer than two runs or they do not vary (sd 0): then there is no spread to compare with.
double relative_score(double value, const BenchmarkStats& stats);

// One score of an expert run, as the record keeps it.
struct ExpertScore {
  std::string task;
  std::string metric;
  double value = 0;
  std::string unit;
};

// A task's metric over the expert runs: its unit (the first run's) and statistics.
struct Benchmark {
  std::string unit;
  BenchmarkStats stats;
};

// The expert runs' scores grouped by (task, metric) and summarised, in key order; non-finite
// values (a metric an expert run could not measure) are left out, and a group left empty is
// dropped.
std::map<std::pair<std::string, std::string>, Benchmark> group_benchmarks(
    std::span<const ExpertScore> scores);

}  // namespace incise::curriculum
