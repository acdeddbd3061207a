// A station's calibration: devices/station_calibration.h (the default, and the checks of one
// built in code; its JSON is station_calibration_json_test.cpp).

#include "devices/station_calibration.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "devices/device_state.h"
#include "kinematics_fixtures.h"

namespace incise::devices {
namespace {

TEST(StationCalibration, DefaultIsTwoPensWithIdentityMappings) {
  const StationCalibration c = default_station_calibration();
  EXPECT_EQ(check_station_calibration(c), "");
  for (int index : {0, 1}) {
    const DeviceCalibration* device = c.find(index);
    ASSERT_NE(device, nullptr);
    EXPECT_EQ(device->kind, DeviceKind::Pen);
    const Vec3 p{0.1, -0.2, 0.3};
    EXPECT_EQ(device->mapping.to_scene(p), p);
    EXPECT_EQ(device->mapping.force_to_device(p), p);
  }
  EXPECT_EQ(c.find(2), nullptr);
}

TEST(StationCalibration, CheckRefusesNonFiniteValuesBuiltInCode) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  StationCalibration c = sample_calibration();
  c.devices[1].mapping.scale = inf;
  EXPECT_EQ(check_station_calibration(c), "devices[1].mapping.scale: must be finite, got inf");
  c = sample_calibration();
  c.devices[1].mapping.scale = nan;
  EXPECT_EQ(check_station_calibration(c), "devices[1].mapping.scale: must be finite, got nan");
  c = sample_calibration();
  c.devices[1].mapping.offset.y = -inf;
  EXPECT_EQ(check_station_calibration(c),
            "devices[1].mapping.offset: must be finite, got [0.333333, -inf, -0.125]");
  c = sample_calibration();
  c.devices[0].mapping.rotation.x = nan;
  EXPECT_EQ(check_station_calibration(c).rfind("devices[0].mapping.rotation: must be finite", 0),
            0u);
  c = sample_calibration();
  c.devices[0].scope.portal.z = inf;
  EXPECT_EQ(check_station_calibration(c),
            "devices[0].scope.portal: must be finite, got [0.04, "
            "0.05, inf]");
  c = sample_calibration();
  c.devices[0].scope.max_insertion = inf;
  EXPECT_EQ(check_station_calibration(c),
            "devices[0].scope.insertion_limits_m: must satisfy 0 <= min < max, got [0.01, inf]");
  // A pen's unused scope geometry is not checked.
  c = sample_calibration();
  c.devices[1].scope.max_insertion = inf;
  EXPECT_EQ(check_station_calibration(c), "");
}

}  // namespace
}  // namespace incise::devices
