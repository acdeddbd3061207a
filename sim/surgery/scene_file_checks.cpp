// The value checks of the scene and script file readers.
#include "sim/surgery/scene_file_checks.h"

#include <cstdint>

#include "sim/scene/scene_error.h"
#include "sim/scene/scene_validation.h"

namespace incise::sim::surgery {

void check_range(const std::string& path, Real value, Real lo, bool lo_closed, Real hi,
                 bool hi_closed) {
  const bool above = lo_closed ? value >= lo : value > lo;
  const bool below = hi_closed ? value <= hi : value < hi;
  if (above && below) return;
  std::string range;
  if (hi == kInfinity) {
    range = std::string(lo_closed ? ">= " : "> ") + format_number(lo);
  } else {
    range = std::string("in ") + (lo_closed ? "[" : "(") + format_number(lo) + ", " +
            format_number(hi) + (hi_closed ? "]" : ")");
  }
  throw SceneError(path, "must be " + range + " (got " + format_number(value) + ")");
}

int read_count(const JsonObjectReader& object, std::string_view key, int lo, int hi) {
  const std::int64_t n = object.integer(key);
  if (n < lo || n > hi) {
    throw SceneError(object.path(key), "must be in [" + std::to_string(lo) + ", " +
                                           std::to_string(hi) + "] (got " + std::to_string(n) +
                                           ")");
  }
  return static_cast<int>(n);
}

}  // namespace incise::sim::surgery
