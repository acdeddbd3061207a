#include "sim/tools/tool_checks.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace incise::sim::tools::checks {

void check_vector(const Vec3& value, const char* where, const char* what) {
  if (value.allFinite()) return;
  std::ostringstream message;
  message << where << ": " << what << " must be finite, got (" << value.x() << ", " << value.y()
          << ", " << value.z() << ")";
  throw std::invalid_argument(message.str());
}

void check_radius(Real radius, const char* where) {
  if (radius > 0 && std::isfinite(radius)) return;
  throw std::invalid_argument(std::string(where) + ": tool radius must be finite and > 0, got " +
                              std::to_string(radius));
}

void check_sphere(const collide::Sphere& sphere, const char* where) {
  check_radius(sphere.radius, where);
  check_vector(sphere.centre, where, "sphere centre");
}

void check_capsule(const collide::Capsule& capsule, const char* where) {
  check_radius(capsule.radius, where);
  check_vector(capsule.a, where, "capsule end a");
  check_vector(capsule.b, where, "capsule end b");
}

}  // namespace incise::sim::tools::checks
