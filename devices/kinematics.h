#pragma once
// Device kinematics of a haptic station: how each device's readings become a tool pose in the
// scene, and how a scene force becomes what the device's motors render.
//
//   WorkspaceMapping    device frame -> scene frame (scale, rotation, offset) and forces back
//   PortalScope         4-DOF arthroscope/laparoscope pivoting about a fulcrum at the portal:
//                       pitch, yaw, insertion (actuated) and roll (free), 30-degree optics
//   PenDevice           6-DOF pen (Phantom-like): 3 actuated translations + a passive gimbal
//   StationCalibration  per-device kind, mapping and scope geometry, stored as JSON
//
// Units: metres, radians, newtons, newton-metres. Values cross this interface as the plain
// devices::Vec3 / Quat of the wire protocol; Eigen is used inside and for the Jacobian.
// Nothing here allocates except the calibration functions and the PortalScope constructor's
// check, so the kinematics may run in the 1 kHz haptic loop.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "devices/device_state.h"
#include "devices/parse_result.h"
#include "devices/protocol.h"

namespace incise::devices {

inline Eigen::Vector3d to_eigen(const Vec3& v) {
  return {v.x, v.y, v.z};
}
inline Eigen::Quaterniond to_eigen(const Quat& q) {
  return {q.w, q.x, q.y, q.z};
}
inline Vec3 to_vec3(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}
inline Quat to_quat(const Eigen::Quaterniond& q) {
  return {q.w(), q.x(), q.y(), q.z()};
}

inline constexpr double kDegree = std::numbers::pi / 180.0;  // [rad]

// ---------------------------------------------------------------------------------------------
// Device frame -> scene frame:  x_scene = R (s x_device) + o.
//
// Forces go the other way by the transpose, scaled so that virtual work is preserved: a device
// displacement dx_dev moves the tool by dx_scene = s R dx_dev in the scene, so the force the
// hand must feel is the one doing the same work,
//   F_dev . dx_dev = F_scene . dx_scene = F_scene . (s R dx_dev)  =>  F_dev = s R^T F_scene.
// A scale > 1 (small hand motions, large scene motions) therefore makes scene forces feel
// stronger, exactly as a lever would. Stiffness follows as K_dev = s^2 R^T K_scene R.
struct WorkspaceMapping {
  double scale = 1.0;  // s > 0, scene metres per device metre
  Quat rotation;       // R, unit quaternion
  Vec3 offset;         // o, where the device origin lands in the scene [m]

  Vec3 to_scene(const Vec3& p_device) const;
  Vec3 to_device(const Vec3& p_scene) const;
  // A velocity or displacement: no offset.
  Vec3 displacement_to_scene(const Vec3& d_device) const;
  Vec3 displacement_to_device(const Vec3& d_scene) const;
  // q_scene = R q_device (the scale does not affect directions).
  Quat orientation_to_scene(const Quat& q_device) const;
  Quat orientation_to_device(const Quat& q_scene) const;
  // F_dev = s R^T F_scene (see above).
  Vec3 force_to_device(const Vec3& f_scene) const;
  Vec3 force_to_scene(const Vec3& f_device) const;
  // Position and orientation into the scene; index, buttons and jaw unchanged.
  DeviceState state_to_scene(const DeviceState& device) const;
  // A scene-frame local force model as the device renders it: reference point to_device,
  // force force_to_device, K_dev = s^2 R^T K R. Then for every device point x,
  //   device_model.force(x) == force_to_device(scene_model.force(to_scene(x))).
  ForceModel force_model_to_device(const ForceModel& scene_model) const;
};

// ---------------------------------------------------------------------------------------------
// The arthroscope (or laparoscope) of a two-handed station (Knee Arthroscopy VR, Fig. 3): the shaft
// pivots about a fulcrum at the portal in the skin, so the tool has 4 DOF. Pitch, yaw and insertion
// carry force feedback; roll (the knob turning the 30-degree optics) is free.
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
  // The zoom (Knee Arthroscopy VR, section III: "the field-of-view is also adjustable"), clamped
  // to [kMinFieldOfView, kMaxFieldOfView].
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

// ---------------------------------------------------------------------------------------------
// A pen-style 6-DOF device (Phantom-like, Knee Arthroscopy VR, Fig. 1): three actuated
// translational axes move the gimbal centre, which is the tool point; three passive gimbal angles
// orient the pen.
//   orientation = Ry(yaw) Rx(pitch) Rz(roll),  the pen points along its +z (as the scope)
// Gimbal lock at pitch = +-90 degrees: yaw and roll then turn about the same axis, and
// inverse() returns yaw = 0 with the whole turn in roll (the pose still round-trips).
// The motors render the tip force unchanged; the gimbal has no motors, so torques are not
// rendered (Knee Arthroscopy VR, Fig. 1(b)): joint_forces() returns the dropped torque for logging.

struct PenJoints {
  Vec3 position;       // gimbal centre = tool point, device frame [m]
  double yaw = 0.0;    // [rad]
  double pitch = 0.0;  // [rad]
  double roll = 0.0;   // [rad]
};

struct PenPose {
  Vec3 position;  // [m]
  Quat orientation;
};

struct PenForces {
  Vec3 axis_forces_n;      // along the device's x, y, z axes
  Vec3 dropped_torque_nm;  // the part of the requested wrench the device cannot render
};

struct PenDevice {
  PenPose forward(const PenJoints& joints) const;
  // Yaw and roll in [-pi, pi], pitch in [-pi/2, pi/2].
  PenJoints inverse(const PenPose& pose) const;
  PenForces joint_forces(const Vec3& tip_force_n, const Vec3& tip_torque_nm = {}) const;
};

// ---------------------------------------------------------------------------------------------
// A station's calibration as stored in the database:
//
//   {"devices": [
//     {"index": 0, "kind": "pen",
//      "mapping": {"scale": 1.0, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]}},
//     {"index": 1, "kind": "scope",
//      "mapping": {"scale": 1.0, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]},
//      "scope": {"portal": [0.04, 0.04, 0.08], "portal_orientation": [0, 1, 0, 0],
//                "view_angle_deg": 30, "field_of_view_deg": 70, "insertion_limits_m": [0, 0.2],
//                "pitch_limits_deg": [-60, 60], "yaw_limits_deg": [-60, 60]}}]}
//
// devices: 1 to kMaxStationDevices (protocol.h) entries with distinct index 0 or 1. kind: "pen" or
// "scope". mapping: all three keys required, scale > 0, rotation a unit quaternion w, x, y, z (|q|
// within kUnitQuaternionTolerance of 1; normalised on reading), offset [m]. scope: required for a
// scope and refused for a pen; portal, portal_orientation and insertion_limits_m required, the
// rest default as in ScopeGeometry. Unknown keys are errors; every number must be finite.

enum class DeviceKind { Pen, Scope };

struct DeviceCalibration {
  int index = 0;  // the DeviceState::device_index it applies to
  DeviceKind kind = DeviceKind::Pen;
  WorkspaceMapping mapping;
  ScopeGeometry scope;  // used only when kind == Scope
};

struct StationCalibration {
  std::vector<DeviceCalibration> devices;  // in stored order
  // The entry for device_index, or nullptr.
  const DeviceCalibration* find(int device_index) const;
};

// Two pens, indices 0 and 1, identity mappings: device frame = scene frame.
StationCalibration default_station_calibration();

// The first rule of the format above that calibration breaks, as `<path>: <problem>`, e.g.
// `devices[1].mapping.scale: must be > 0, got -2`, or "".
std::string check_station_calibration(const StationCalibration& calibration);

// Errors as check_station_calibration's, or `not valid JSON: ...`, or a type error such as
// `devices[0].mapping.offset[2]: must be a number, got string`.
ParseResult<StationCalibration> parse_station_calibration(std::string_view json_text);

// The format above, compact. Numbers are printed in full precision; angles are stored in
// degrees, so they read back within a rounding error (~1e-16 relative).
std::string station_calibration_json(const StationCalibration& calibration);

}  // namespace incise::devices
