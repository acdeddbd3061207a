#pragma once
// Test helpers shared by the metric tests: a metric's value by key, the message a call throws.

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <stdexcept>
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

// The message of the std::invalid_argument #f throws ("" if it does not throw).
inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace incise::curriculum::testing
