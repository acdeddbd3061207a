#pragma once
// Reading JSON documents (scripts, calibrations) with errors that name the path of the bad value,
// e.g. `waypoints[2].position[1]: must be a number, got string`. Internal to devices/: the
// sources that parse JSON include it; no public header does.

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace incise::devices::json_read {

inline std::string index_path(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

inline std::string wrong_type(const std::string& path, const char* expected,
                              const nlohmann::json& value) {
  return path + ": must be " + expected + ", got " + value.type_name();
}

inline std::string read_number(const nlohmann::json& value, const std::string& path, double& out) {
  if (!value.is_number()) return wrong_type(path, "a number", value);
  out = value.get<double>();
  return {};
}

// Reads an array of exactly n numbers into out[0..n).
inline std::string read_numbers(const nlohmann::json& value, const std::string& path, std::size_t n,
                                double* out) {
  if (!value.is_array()) return wrong_type(path, "an array", value);
  if (value.size() != n) {
    return path + ": must have " + std::to_string(n) + " numbers, got " +
           std::to_string(value.size());
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (auto error = read_number(value[i], index_path(path, i), out[i]); !error.empty()) {
      return error;
    }
  }
  return {};
}

}  // namespace incise::devices::json_read
