// A station's calibration as JSON: devices/station_calibration_json.h. Round trips, the
// documented example, defaults and a precise error for every bad input.

#include "devices/station_calibration_json.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "devices/device_state.h"
#include "devices/eigen_conversions.h"
#include "devices/portal_scope.h"
#include "devices/station_calibration.h"
#include "kinematics_fixtures.h"

namespace incise::devices {
namespace {

void expect_same(const StationCalibration& a, const StationCalibration& b) {
  ASSERT_EQ(a.devices.size(), b.devices.size());
  const auto near = [](const auto& x, const auto& y) {
    return (to_eigen(x) - to_eigen(y)).norm() < 1e-15;
  };
  for (std::size_t i = 0; i < a.devices.size(); ++i) {
    const DeviceCalibration &x = a.devices[i], &y = b.devices[i];
    EXPECT_EQ(x.index, y.index);
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_EQ(x.mapping.scale, y.mapping.scale);
    EXPECT_TRUE(to_eigen(x.mapping.rotation)
                    .coeffs()
                    .isApprox(to_eigen(y.mapping.rotation).coeffs(), 1e-15));
    EXPECT_TRUE(near(x.mapping.offset, y.mapping.offset));
    if (x.kind != DeviceKind::Scope) continue;
    const ScopeGeometry &s = x.scope, &t = y.scope;
    EXPECT_TRUE(near(s.portal, t.portal));
    EXPECT_TRUE(to_eigen(s.portal_orientation)
                    .coeffs()
                    .isApprox(to_eigen(t.portal_orientation).coeffs(), 1e-15));
    const std::pair<double, double> pairs[] = {{s.view_angle, t.view_angle},
                                               {s.field_of_view, t.field_of_view},
                                               {s.min_insertion, t.min_insertion},
                                               {s.max_insertion, t.max_insertion},
                                               {s.min_pitch, t.min_pitch},
                                               {s.max_pitch, t.max_pitch},
                                               {s.min_yaw, t.min_yaw},
                                               {s.max_yaw, t.max_yaw}};
    for (const auto& [u, v] : pairs)
      EXPECT_NEAR(u, v, 1e-15);
  }
}

TEST(StationCalibration, JsonRoundTrips) {
  const StationCalibration c = sample_calibration();
  ASSERT_EQ(check_station_calibration(c), "");
  const std::string text = station_calibration_json(c);
  const auto parsed = parse_station_calibration(text);
  ASSERT_TRUE(parsed) << parsed.error << "\n" << text;
  expect_same(*parsed.value, c);
  ASSERT_NE(parsed.value->find(1), nullptr);
  EXPECT_EQ(parsed.value->find(1)->kind, DeviceKind::Scope);
  // Printing what was read and reading it again changes nothing.
  const auto again = parse_station_calibration(station_calibration_json(*parsed.value));
  ASSERT_TRUE(again) << again.error;
  expect_same(*again.value, *parsed.value);
}

TEST(StationCalibration, DocumentedExampleParses) {
  const auto parsed = parse_station_calibration(R"({"devices": [
    {"index": 0, "kind": "pen",
     "mapping": {"scale": 1.0, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]}},
    {"index": 1, "kind": "scope",
     "mapping": {"scale": 1.0, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]},
     "scope": {"portal": [0.04, 0.04, 0.08], "portal_orientation": [0, 1, 0, 0],
               "view_angle_deg": 30, "field_of_view_deg": 70, "insertion_limits_m": [0, 0.2],
               "pitch_limits_deg": [-60, 60], "yaw_limits_deg": [-60, 60]}}]})");
  ASSERT_TRUE(parsed) << parsed.error;
  const DeviceCalibration& scope = parsed.value->devices[1];
  EXPECT_EQ(scope.kind, DeviceKind::Scope);
  EXPECT_NEAR(scope.scope.view_angle, kPi / 6, 1e-15);
  EXPECT_NEAR(scope.scope.max_yaw, kPi / 3, 1e-15);
  EXPECT_EQ(scope.scope.max_insertion, 0.2);
  // The portal is turned half a turn about x: the shaft points down (-z) into the tissue.
  const PortalScope portal_scope(scope.scope);
  const ScopePose pose = portal_scope.forward({0, 0, 0.05, 0});
  EXPECT_NEAR(pose.tip.z, 0.03, 1e-15);
}

TEST(StationCalibration, OptionalScopeKeysTakeTheirDefaults) {
  const auto parsed = parse_station_calibration(R"({"devices": [{"index": 1, "kind": "scope",
    "mapping": {"scale": 2, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]},
    "scope": {"portal": [0, 0, 0], "portal_orientation": [1, 0, 0, 0],
              "insertion_limits_m": [0.01, 0.1]}}]})");
  ASSERT_TRUE(parsed) << parsed.error;
  const ScopeGeometry& g = parsed.value->devices[0].scope;
  const ScopeGeometry defaults;
  EXPECT_EQ(g.view_angle, defaults.view_angle);
  EXPECT_EQ(g.field_of_view, defaults.field_of_view);
  EXPECT_EQ(g.min_pitch, defaults.min_pitch);
  EXPECT_EQ(g.max_yaw, defaults.max_yaw);
  EXPECT_EQ(g.min_insertion, 0.01);
}

TEST(StationCalibration, NearlyUnitQuaternionsAreNormalised) {
  const auto parsed = parse_station_calibration(R"({"devices": [{"index": 0, "kind": "pen",
    "mapping": {"scale": 1, "rotation": [0.6, 0.8004, 0, 0], "offset": [0, 0, 0]}}]})");
  ASSERT_TRUE(parsed) << parsed.error;
  const Quat q = parsed.value->devices[0].mapping.rotation;
  EXPECT_NEAR(to_eigen(q).norm(), 1.0, 1e-15);
  EXPECT_NEAR(q.x / q.w, 0.8004 / 0.6, 1e-12);  // same rotation, only rescaled
}

// A station of the given device entries (JSON text), and entries to build them from.
std::string station(const std::string& devices) {
  return R"({"devices": [)" + devices + "]}";
}
const std::string kIdentity = R"({"scale": 1, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]})";
std::string pen(const std::string& index = "0", const std::string& mapping = kIdentity,
                const std::string& kind = R"("pen")") {
  return R"({"index": )" + index + R"(, "kind": )" + kind + R"(, "mapping": )" + mapping + "}";
}
std::string scope(const std::string& geometry_extra, const std::string& index = "1") {
  return R"({"index": )" + index + R"(, "kind": "scope", "mapping": )" + kIdentity +
         R"(, "scope": {"portal": [0, 0, 0], "portal_orientation": [1, 0, 0, 0])" + geometry_extra +
         "}}";
}
const std::string kLimits = R"(, "insertion_limits_m": [0, 0.2])";

TEST(StationCalibration, BadInputsGetPreciseErrors) {
  struct Case {
    std::string json;
    std::string error;
  };
  const std::vector<Case> cases = {
      {"[]", "(calibration): must be an object, got array"},
      {"{}", "devices: missing"},
      {R"({"devices": {}})", "devices: must be an array, got object"},
      {station(""), "devices: must list at least one device"},
      {station(pen() + "," + pen("1") + "," + pen("1")), "devices: at most 2 devices, got 3"},
      {R"({"devices": [], "stations": 1})", "stations: unknown key (a calibration has devices)"},
      {station("7"), "devices[0]: must be an object, got number"},
      {station(pen() + "," +
               pen("1", R"({"scale": -2, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]})")),
       "devices[1].mapping.scale: must be > 0, got -2"},
      {station(pen("0", R"({"scale": 0, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]})")),
       "devices[0].mapping.scale: must be > 0, got 0"},
      {station(pen("0", R"({"scale": "1", "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]})")),
       "devices[0].mapping.scale: must be a number, got string"},
      {station(pen("0", R"({"scale": 1, "rotation": [2, 0, 0, 0], "offset": [0, 0, 0]})")),
       "devices[0].mapping.rotation: must be a unit quaternion (|q| within 0.001 of 1), got |q| "
       "= 2"},
      {station(pen("0", R"({"scale": 1, "rotation": [1, 0, 0], "offset": [0, 0, 0]})")),
       "devices[0].mapping.rotation: must have 4 numbers, got 3"},
      {station(pen("0", R"({"scale": 1, "rotation": [1, 0, 0, 0], "offset": [0, null, 0]})")),
       "devices[0].mapping.offset[1]: must be a number, got null"},
      {station(pen("0", R"({"scale": 1, "rotation": [1, 0, 0, 0]})")),
       "devices[0].mapping.offset: missing"},
      {station(pen("0", R"({"scale": 1, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0],
                            "shift": 1})")),
       "devices[0].mapping.shift: unknown key (a mapping has scale, rotation and offset)"},
      {station(pen("0", kIdentity, R"("laser")")),
       R"(devices[0].kind: must be "pen" or "scope", got "laser")"},
      {station(R"({"index": 0, "mapping": )" + kIdentity + "}"), "devices[0].kind: missing"},
      {station(pen("2")), "devices[0].index: must be 0 or 1, got 2"},
      {station(pen("0.5")), "devices[0].index: must be 0 or 1, got 0.5"},
      {station(pen(R"("0")")), "devices[0].index: must be 0 or 1, got string"},
      {station(pen() + "," + scope(kLimits, "0")),
       "devices[1].index: device 0 is already calibrated by devices[0]"},
      {station(R"({"index": 0, "kind": "pen", "mapping": )" + kIdentity + R"(, "tool": 1})"),
       "devices[0].tool: unknown key (a device has index, kind, mapping and scope)"},
      {station(R"({"index": 0, "kind": "pen", "mapping": )" + kIdentity + R"(, "scope": {}})"),
       "devices[0].scope: only a scope device has scope geometry, this one is a pen"},
      {station(R"({"index": 1, "kind": "scope", "mapping": )" + kIdentity + R"(, "scope": {}})"),
       "devices[0].scope.portal: missing"},
      {station(R"({"index": 1, "kind": "scope", "mapping": )" + kIdentity + "}"),
       "devices[0].scope: missing (a scope device needs its geometry)"},
      {station(pen() + "," + scope("")), "devices[1].scope.insertion_limits_m: missing"},
      {station(pen() + "," + scope(kLimits + R"(, "view_angle_deg": 95)")),
       "devices[1].scope.view_angle_deg: must be in [0, 90), got 95"},
      {station(pen() + "," + scope(kLimits + R"(, "view_angle_deg": -5)")),
       "devices[1].scope.view_angle_deg: must be in [0, 90), got -5"},
      {station(pen() + "," + scope(kLimits + R"(, "field_of_view_deg": 200)")),
       "devices[1].scope.field_of_view_deg: must be in [10, 140], got 200"},
      {station(pen() + "," + scope(R"(, "insertion_limits_m": [0.3, 0.1])")),
       "devices[1].scope.insertion_limits_m: must satisfy 0 <= min < max, got [0.3, 0.1]"},
      {station(pen() + "," + scope(R"(, "insertion_limits_m": [-0.1, 0.1])")),
       "devices[1].scope.insertion_limits_m: must satisfy 0 <= min < max, got [-0.1, 0.1]"},
      {station(pen() + "," + scope(kLimits + R"(, "pitch_limits_deg": [-100, 60])")),
       "devices[1].scope.pitch_limits_deg: must satisfy -90 < min < max < 90, got [-100, 60]"},
      {station(pen() + "," + scope(kLimits + R"(, "yaw_limits_deg": [30, 20])")),
       "devices[1].scope.yaw_limits_deg: must satisfy -90 < min < max < 90, got [30, 20]"},
      {station(pen() + "," + scope(kLimits + R"(, "yaw_limits_deg": [30])")),
       "devices[1].scope.yaw_limits_deg: must have 2 numbers, got 1"},
      {station(pen() + "," + scope(kLimits + R"(, "zoom": 2)")),
       "devices[1].scope.zoom: unknown key (a scope has portal, portal_orientation, "
       "view_angle_deg, field_of_view_deg, insertion_limits_m, pitch_limits_deg and "
       "yaw_limits_deg)"},
      {station(R"({"index": 1, "kind": "scope", "mapping": )" + kIdentity +
               R"(, "scope": {"portal": [0, 0, 0], "portal_orientation": [0, 0, 0, 0],
                              "insertion_limits_m": [0, 0.2]}})"),
       "devices[0].scope.portal_orientation: must be a unit quaternion (|q| within 0.001 of 1), "
       "got |q| = 0"},
      // Numbers beyond a double never become infinities: the JSON reader refuses them.
      {station(pen("0", R"({"scale": 1e999, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]})")),
       "not valid JSON: number overflow parsing '1e999'"},
  };
  for (const Case& c : cases) {
    const auto parsed = parse_station_calibration(c.json);
    EXPECT_FALSE(parsed) << c.json;
    EXPECT_EQ(parsed.error, c.error) << c.json;
  }
  // Syntax errors keep the reader's position.
  const auto parsed = parse_station_calibration(R"({"devices": [})");
  EXPECT_EQ(parsed.error.rfind("not valid JSON: parse error at line 1, column 14", 0), 0u)
      << parsed.error;
}

}  // namespace
}  // namespace incise::devices
