#pragma once
// Internal to the kinematics (portal_scope.cpp, station_calibration.cpp): the checks of
// calibration values, whose messages name the path and units of the stored JSON.

#include <initializer_list>
#include <string>

#include "devices/device_state.h"

namespace incise::devices {

// value as %g.
std::string number(double value);
// "[a, b, c]".
std::string numbers(std::initializer_list<double> values);
bool finite(std::initializer_list<double> values);
// "" or `<path>: <problem>`.
std::string check_unit_quaternion(const Quat& q, const std::string& path);
std::string check_point(const Vec3& p, const std::string& path);
// low < high, both strictly inside (-kMaxPivotAngle, kMaxPivotAngle); the message in degrees.
std::string check_angle_limits(double low, double high, const std::string& path);

}  // namespace incise::devices
