#pragma once
// Shared by the tests of server/live/: the real palpation scene as the server embeds it, and a
// scripted probe that circles above the tissue and dips into it, so that runs have contact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "devices/device_state.h"
#include "server/live/scene_library.h"
#include "server/live/tick_record.h"
#include "sim/core/types.h"
#include "sim/io/scene_json.h"
#include "sim/scene/scene.h"

namespace incise::server::live::test {

inline constexpr const char* kPalpationId = "scenes/palpation.json";
inline constexpr double kTickS = 0.002;  // the live sessions' 500 Hz tick: 8 sub-steps of 2.5e-4 s

// Geometry of palpation.json: an 8 x 8 x 3 cm block on z = 0, a probe of radius 5 mm, top nodes
// every 8/12 cm.
inline constexpr double kTopZ = 0.03;
inline constexpr double kCentreXY = 0.04;
inline constexpr double kToolRadius = 0.005;

inline std::string palpation_text() {
  const auto source = find_scene(kPalpationId);
  if (!source) throw std::runtime_error("scenes/palpation.json is not embedded");
  return std::string(source->text);
}

inline sim::Scene palpation_scene() {
  return sim::parse_scene_text(palpation_text());
}

// The probe at tick n of the script: it circles 1 cm around the block's centre every 1.6 s and,
// for the first half of every second, dips to 6 mm below where it would touch the undeformed top
// face. The other fields change too, so that a recording of them shows a swapped field.
inline devices::DeviceState scripted_input(std::int64_t tick) {
  const double t = static_cast<double>(tick) * kTickS;
  const double dip = std::max(0.0, std::sin(2 * std::numbers::pi * t));
  devices::DeviceState s;
  s.buttons = static_cast<std::uint8_t>(tick % 4);
  s.jaw = static_cast<float>(0.5 + 0.5 * std::cos(t));
  s.position = {kCentreXY + 0.01 * std::cos(2 * std::numbers::pi * t / 1.6),
                kCentreXY + 0.01 * std::sin(2 * std::numbers::pi * t / 1.6),
                kTopZ + kToolRadius + 0.002 - 0.008 * dip};
  const double half = 0.1 * t;
  s.orientation = {std::cos(half), 0.0, 0.0, std::sin(half)};
  return s;
}

// The script as a recording of `count` ticks (forces left at zero: a replay does not read them).
inline std::vector<TickRecord> scripted_records(std::int64_t count) {
  std::vector<TickRecord> records(static_cast<std::size_t>(count));
  for (std::int64_t i = 0; i < count; ++i) {
    records[static_cast<std::size_t>(i)].tick = static_cast<std::uint32_t>(i);
    records[static_cast<std::size_t>(i)].input = scripted_input(i);
  }
  return records;
}

// Bit-for-bit equality of two position arrays (also tells -0 from 0, which == does not).
inline ::testing::AssertionResult same_bits(const sim::Points& a, const sim::Points& b) {
  if (a.rows() != b.rows()) {
    return ::testing::AssertionFailure() << a.rows() << " rows vs " << b.rows();
  }
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    if (std::memcmp(a.row(i).data(), b.row(i).data(), 3 * sizeof(double)) != 0) {
      return ::testing::AssertionFailure()
             << "node " << i << ": " << a.row(i) << " vs " << b.row(i);
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace incise::server::live::test
