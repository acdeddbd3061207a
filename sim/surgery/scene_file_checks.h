#pragma once
// Internal to the scene and script file readers (scene_file.cpp, tool_script.cpp): value checks
// that throw SceneError at a JSON path, and the lists their messages name.

#include <limits>
#include <string>
#include <string_view>

#include "sim/core/types.h"
#include "sim/io/json_object_reader.h"

namespace incise::sim::surgery {

inline constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

// "a, b, c" of a list of names.
template <typename Names>
inline std::string joined(const Names& names) {
  std::string text;
  for (const auto& name : names)
    text += (text.empty() ? "" : ", ") + std::string(name);
  return text;
}

// value in (lo, hi) with either end closed on request, else SceneError at path.
void check_range(const std::string& path, Real value, Real lo, bool lo_closed, Real hi,
                 bool hi_closed);

// The integer at key, in [lo, hi], else SceneError at its path.
int read_count(const JsonObjectReader& object, std::string_view key, int lo, int hi);

}  // namespace incise::sim::surgery
