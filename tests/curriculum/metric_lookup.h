#pragma once
// Test helper shared by the metric tests: a metric's value by key.

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "curriculum/metrics.h"

namespace incise::curriculum::testing {

// The value of the metric with this key; fails the test (and returns NaN) when it is missing.
inline double metric(const std::vector<MetricValue>& values, const std::string& key) {
  for (const auto& v : values)
    if (v.key == key) return v.value;
  ADD_FAILURE() << "no metric " << key;
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace incise::curriculum::testing
