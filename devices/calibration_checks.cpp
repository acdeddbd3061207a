// The checks of calibration values shared by the scope geometry and the station calibration.
#include "devices/calibration_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "devices/portal_scope.h"
#include "devices/protocol.h"

namespace incise::devices {

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::string numbers(std::initializer_list<double> values) {
  std::string text = "[";
  for (double v : values)
    text += (text.size() > 1 ? ", " : "") + number(v);
  return text + "]";
}

bool finite(std::initializer_list<double> values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

std::string check_unit_quaternion(const Quat& q, const std::string& path) {
  if (!finite({q.w, q.x, q.y, q.z})) {
    return path + ": must be finite, got " + numbers({q.w, q.x, q.y, q.z});
  }
  const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!(std::abs(norm - 1.0) <= kUnitQuaternionTolerance)) {
    return path + ": must be a unit quaternion (|q| within " + number(kUnitQuaternionTolerance) +
           " of 1), got |q| = " + number(norm);
  }
  return {};
}

std::string check_point(const Vec3& p, const std::string& path) {
  if (finite({p.x, p.y, p.z})) return {};
  return path + ": must be finite, got " + numbers({p.x, p.y, p.z});
}

// low < high, both strictly inside (-bound, bound); the message in degrees.
std::string check_angle_limits(double low, double high, const std::string& path) {
  const double bound = kMaxPivotAngle;
  if (finite({low, high}) && -bound < low && low < high && high < bound) return {};
  return path + ": must satisfy " + number(-bound / kDegree) + " < min < max < " +
         number(bound / kDegree) + ", got " + numbers({low / kDegree, high / kDegree});
}

}  // namespace incise::devices
