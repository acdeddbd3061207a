#pragma once
// The 4-DOF arthroscope/laparoscope pivoting about a fulcrum at the portal: pitch, yaw,
// insertion (actuated) and roll (free), with its angled optics. Part of the station kinematics
// (kinematics.h).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <numbers>
#include <string>
#include <string_view>

#include "devices/device_state.h"

namespace incise::devices {

inline constexpr double kDegree = std::numbers::pi / 180.0;  // [rad]

// The arthroscope (or laparoscope) of a two-handed station (Knee Arthroscopy VR, section III,
// Fig. 3): the shaft pivots about a fulcrum at the portal in the skin, so the tool has 4 DOF.
// Pitch, yaw and insertion carry force feedback; roll (the knob turning the 30-degree optics) is
// free.
//
// Convention. P = portal_orientation; its +z is the shaft direction into the body at rest.
//   shaft orientation  Q = P Ry(yaw) Rx(pitch) Rz(roll)        (yaw: outer axis, fixed to P)
//   shaft direction    d = Q e_z = P (cos(pitch) sin(yaw), -sin(pitch), cos(pitch) cos(yaw))
//   tip                t = portal + insertion d
// Insertion is the tip's distance from the portal along the shaft. Positive pitch tilts the
// shaft toward -y of P, positive yaw toward +x of P. Pitch and yaw limits lie inside
// (-90, 90) degrees, so the shaft always points into the body (d . P e_z > 0) and the
// convention never reaches its singularity at pitch = +-90 degrees.
//
// Optics: the view is tilted from the shaft by view_angle toward the shaft frame's +y,
//   view_direction = Q (0, sin a, cos a),   view_up = Q (0, cos a, -sin a),
// so rolling turns the view around the shaft on a cone of half-angle a, and view_up (the top
// of the image) lies in the plane of shaft and view, on the side the view leans to.

struct ScopeJoints {
  double pitch = 0.0;      // [rad]
  double yaw = 0.0;        // [rad]
  double insertion = 0.0;  // [m]
  double roll = 0.0;       // [rad], unlimited; inverse() returns it in [-pi, pi]
  friend bool operator==(const ScopeJoints&, const ScopeJoints&) = default;
};

inline constexpr double kMinFieldOfView = 10.0 * kDegree;   // narrower is a typo
inline constexpr double kMaxFieldOfView = 140.0 * kDegree;  // wider than any arthroscope
inline constexpr double kMaxViewAngle = 90.0 * kDegree;     // exclusive: 0, 30, 45, 70 are sold
inline constexpr double kMaxPivotAngle = 90.0 * kDegree;    // exclusive bound of |pitch|, |yaw|

struct ScopeGeometry {
  Vec3 portal;                            // fulcrum, scene frame [m]
  Quat portal_orientation;                // unit; its +z is the shaft direction at pitch = yaw = 0
  double view_angle = 30.0 * kDegree;     // [rad] in [0, kMaxViewAngle)
  double field_of_view = 70.0 * kDegree;  // [rad] full cone angle, [kMin, kMaxFieldOfView]
  double min_insertion = 0.0;             // [m], 0 <= min < max
  double max_insertion = 0.2;             // [m]
  // [rad], each pair -kMaxPivotAngle < min < max < kMaxPivotAngle.
  double min_pitch = -60.0 * kDegree;
  double max_pitch = 60.0 * kDegree;
  double min_yaw = -60.0 * kDegree;
  double max_yaw = 60.0 * kDegree;
  friend bool operator==(const ScopeGeometry&, const ScopeGeometry&) = default;
};

// The first rule above that geometry breaks, as `<path><key>: <problem>` with the key and units
// of the stored JSON (below), e.g. `view_angle_deg: must be in [0, 90), got 95`, or "".
std::string check_scope_geometry(const ScopeGeometry& geometry, const std::string& path = {});

struct ScopePose {
  Vec3 tip;              // [m], scene frame
  Quat shaft;            // +z along the shaft into the body, roll about it
  Vec3 view_direction;   // unit; the shaft tilted by view_angle, turned with the roll
  Vec3 view_up;          // unit, perpendicular to view_direction
  double field_of_view;  // [rad]
};

// Why a tip cannot be reached. inverse() reports the first that applies.
enum class ScopeReach {
  Ok,
  TipAtPortal,         // |tip - portal| < kPortalClearance: the shaft direction is undefined
  BehindPortal,        // the tip is on the outer side of the portal plane (d . P e_z <= 0)
  PitchOutOfRange,     // reachable by the geometry, but outside [min_pitch, max_pitch]
  YawOutOfRange,       //   ... [min_yaw, max_yaw]
  InsertionOutOfRange  //   ... [min_insertion, max_insertion]
};

// E.g. "tip is on or behind the portal plane (outside the body)".
std::string_view describe(ScopeReach reach);

inline constexpr double kPortalClearance = 1e-9;  // [m]
// Limits are met up to this much rounding (rad or m); the solution is then clamped onto them.
inline constexpr double kLimitTolerance = 1e-9;

struct ScopeSolution {
  ScopeReach reach = ScopeReach::Ok;
  // Ok: the joints, within limits. *OutOfRange: the unclamped solution (clamp() it to follow
  // the tip as closely as the device allows). TipAtPortal, BehindPortal: all zero.
  ScopeJoints joints;
  explicit operator bool() const { return reach == ScopeReach::Ok; }
};

// The actuated axes' generalised forces: tau = J^T F without the roll row (roll has no motor).
// These are what the motors exert so that the hand feels F at the tip.
struct ActuatedForces {
  double pitch_torque_nm = 0.0;
  double yaw_torque_nm = 0.0;
  double insertion_force_n = 0.0;
};

class PortalScope {
 public:
  // Throws std::invalid_argument with check_scope_geometry's message if geometry is invalid.
  // The portal orientation is normalised.
  explicit PortalScope(const ScopeGeometry& geometry);

  const ScopeGeometry& geometry() const { return geometry_; }
  // Knee Arthroscopy VR's "adjustable field of view" (zoom), clamped to [kMin, kMaxFieldOfView].
  void set_field_of_view(double radians);

  ScopePose forward(const ScopeJoints& joints) const;

  // The fulcrum fixes pitch, yaw and insertion from the tip alone; roll is passed through
  // (wrapped into [-pi, pi]).
  ScopeSolution inverse(const Vec3& tip, double roll) const;
  // As above, with roll read from the shaft orientation: the angle of its x axis about the
  // shaft, measured in the plane normal to the fulcrum's shaft direction. If shaft disagrees
  // with the tip's direction, this is the roll of the nearest consistent pose.
  ScopeSolution inverse(const Vec3& tip, const Quat& shaft) const;
  ScopeSolution inverse(const ScopePose& pose) const { return inverse(pose.tip, pose.shaft); }

  // d tip / d (pitch, yaw, insertion, roll), scene frame [m/rad, m/rad, 1, m/rad]. The roll
  // column is zero: roll turns the shaft about itself.
  Eigen::Matrix<double, 3, 4> jacobian(const ScopeJoints& joints) const;

  // J^T tip_force on the actuated axes: the statics of a lever about the fulcrum,
  //   pitch, yaw torque = axis . ((tip - portal) x F),  insertion force = d . F,
  // with the yaw axis P e_y and the pitch axis P Ry(yaw) e_x. So a force along the shaft is
  // pure insertion force, and a force F normal to the shaft at insertion L gives a pitch torque
  // L |F| (F also normal to the pitch axis) or a yaw torque L cos(pitch) |F| (F normal to the
  // yaw axis; L cos(pitch) is the tip's distance from it).
  ActuatedForces joint_forces(const ScopeJoints& joints, const Vec3& tip_force) const;

  // Each joint into its limits; roll unchanged.
  ScopeJoints clamp(const ScopeJoints& joints) const;
  bool within_limits(const ScopeJoints& joints) const;

 private:
  ScopeGeometry geometry_;
  Eigen::Vector3d portal_;
  Eigen::Quaterniond portal_orientation_;
};

// Distance of point from the line through pose.tip along the pose's shaft axis [m]. With
// point = the portal this is the fulcrum residual, zero for every pose forward() returns.
double distance_from_shaft_line(const ScopePose& pose, const Vec3& point);

}  // namespace incise::devices
