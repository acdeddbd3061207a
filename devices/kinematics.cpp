#include "devices/kinematics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "devices/json_read.h"

namespace incise::devices {
namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

// Ry(yaw) Rx(pitch) Rz(roll): the rotation order shared by the scope and the pen.
Quaterniond yaw_pitch_roll(double yaw, double pitch, double roll) {
  return Quaterniond(Eigen::AngleAxisd(yaw, Vector3d::UnitY())) *
         Quaterniond(Eigen::AngleAxisd(pitch, Vector3d::UnitX())) *
         Quaterniond(Eigen::AngleAxisd(roll, Vector3d::UnitZ()));
}

// The roll r for which Ry(yaw) Rx(pitch) Rz(r) is nearest to m: the angle of the x axis of
// (Ry Rx)^T m about z. Exact when m has that form; when yaw is ill-determined (near gimbal
// lock) the roll absorbs the error, so the composite rotation stays right.
double residual_roll(const Matrix3d& m, double yaw, double pitch) {
  const Matrix3d rest = yaw_pitch_roll(yaw, pitch, 0.0).toRotationMatrix().transpose() * m;
  return std::atan2(rest(1, 0), rest(0, 0));
}

// Into (-pi, pi].
double wrap_angle(double angle) {
  const double wrapped = std::remainder(angle, 2.0 * std::numbers::pi);
  return wrapped <= -std::numbers::pi ? std::numbers::pi : wrapped;
}

// A limit met up to rounding is met: snap onto it. Returns false if value is farther out.
bool snap_into(double& value, double low, double high) {
  if (value < low - kLimitTolerance || value > high + kLimitTolerance) return false;
  value = std::clamp(value, low, high);
  return true;
}

}  // namespace

// --- WorkspaceMapping --------------------------------------------------------------------------

Vec3 WorkspaceMapping::to_scene(const Vec3& p_device) const {
  return to_vec3(to_eigen(rotation) * (scale * to_eigen(p_device)) + to_eigen(offset));
}

Vec3 WorkspaceMapping::to_device(const Vec3& p_scene) const {
  return to_vec3(to_eigen(rotation).conjugate() * (to_eigen(p_scene) - to_eigen(offset)) / scale);
}

Vec3 WorkspaceMapping::displacement_to_scene(const Vec3& d_device) const {
  return to_vec3(to_eigen(rotation) * (scale * to_eigen(d_device)));
}

Vec3 WorkspaceMapping::displacement_to_device(const Vec3& d_scene) const {
  return to_vec3(to_eigen(rotation).conjugate() * to_eigen(d_scene) / scale);
}

Quat WorkspaceMapping::orientation_to_scene(const Quat& q_device) const {
  return to_quat(to_eigen(rotation) * to_eigen(q_device));
}

Quat WorkspaceMapping::orientation_to_device(const Quat& q_scene) const {
  return to_quat(to_eigen(rotation).conjugate() * to_eigen(q_scene));
}

Vec3 WorkspaceMapping::force_to_device(const Vec3& f_scene) const {
  return to_vec3(scale * (to_eigen(rotation).conjugate() * to_eigen(f_scene)));
}

Vec3 WorkspaceMapping::force_to_scene(const Vec3& f_device) const {
  return to_vec3(to_eigen(rotation) * to_eigen(f_device) / scale);
}

DeviceState WorkspaceMapping::state_to_scene(const DeviceState& device) const {
  DeviceState scene = device;
  scene.position = to_scene(device.position);
  scene.orientation = orientation_to_scene(device.orientation);
  return scene;
}

ForceModel WorkspaceMapping::force_model_to_device(const ForceModel& scene_model) const {
  ForceModel device = scene_model;
  device.reference_position = to_device(scene_model.reference_position);
  device.force = force_to_device(scene_model.force);
  const Matrix3d r = to_eigen(rotation).toRotationMatrix();
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> k(
      scene_model.stiffness.data());
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(device.stiffness.data()) =
      scale * scale * r.transpose() * k * r;
  return device;
}

// --- PortalScope -------------------------------------------------------------------------------

PortalScope::PortalScope(const ScopeGeometry& geometry) : geometry_(geometry) {
  if (std::string error = check_scope_geometry(geometry); !error.empty()) {
    throw std::invalid_argument("scope geometry: " + error);
  }
  portal_ = to_eigen(geometry.portal);
  portal_orientation_ = to_eigen(geometry.portal_orientation).normalized();
  geometry_.portal_orientation = to_quat(portal_orientation_);
}

void PortalScope::set_field_of_view(double radians) {
  geometry_.field_of_view = std::clamp(radians, kMinFieldOfView, kMaxFieldOfView);
}

ScopePose PortalScope::forward(const ScopeJoints& joints) const {
  // Normalised so that rounding in the product of four rotations does not accumulate.
  const Quaterniond shaft =
      (portal_orientation_ * yaw_pitch_roll(joints.yaw, joints.pitch, joints.roll)).normalized();
  const Matrix3d q = shaft.toRotationMatrix();
  const double a = geometry_.view_angle;
  ScopePose pose;
  pose.tip = to_vec3(portal_ + joints.insertion * q.col(2));
  pose.shaft = to_quat(shaft);
  pose.view_direction = to_vec3(std::sin(a) * q.col(1) + std::cos(a) * q.col(2));
  pose.view_up = to_vec3(std::cos(a) * q.col(1) - std::sin(a) * q.col(2));
  pose.field_of_view = geometry_.field_of_view;
  return pose;
}

ScopeSolution PortalScope::inverse(const Vec3& tip, double roll) const {
  ScopeSolution solution;
  const Vector3d from_portal = to_eigen(tip) - portal_;
  const double distance = from_portal.norm();
  if (!(distance >= kPortalClearance)) {
    solution.reach = ScopeReach::TipAtPortal;
    return solution;
  }
  // d in the portal frame: (cos(pitch) sin(yaw), -sin(pitch), cos(pitch) cos(yaw)).
  const Vector3d d = portal_orientation_.conjugate() * (from_portal / distance);
  if (!(d.z() > 0.0)) {
    solution.reach = ScopeReach::BehindPortal;
    return solution;
  }
  ScopeJoints& j = solution.joints;
  j.pitch = std::atan2(-d.y(), std::hypot(d.x(), d.z()));
  j.yaw = std::atan2(d.x(), d.z());
  j.insertion = distance;
  j.roll = wrap_angle(roll);
  const ScopeGeometry& g = geometry_;
  if (!snap_into(j.pitch, g.min_pitch, g.max_pitch)) {
    solution.reach = ScopeReach::PitchOutOfRange;
  } else if (!snap_into(j.yaw, g.min_yaw, g.max_yaw)) {
    solution.reach = ScopeReach::YawOutOfRange;
  } else if (!snap_into(j.insertion, g.min_insertion, g.max_insertion)) {
    solution.reach = ScopeReach::InsertionOutOfRange;
  }
  return solution;
}

ScopeSolution PortalScope::inverse(const Vec3& tip, const Quat& shaft) const {
  ScopeSolution solution = inverse(tip, 0.0);
  if (solution.reach == ScopeReach::TipAtPortal || solution.reach == ScopeReach::BehindPortal) {
    return solution;
  }
  const Matrix3d local =
      (portal_orientation_.conjugate() * to_eigen(shaft).normalized()).toRotationMatrix();
  solution.joints.roll = residual_roll(local, solution.joints.yaw, solution.joints.pitch);
  return solution;
}

Eigen::Matrix<double, 3, 4> PortalScope::jacobian(const ScopeJoints& joints) const {
  const double sp = std::sin(joints.pitch), cp = std::cos(joints.pitch);
  const double sy = std::sin(joints.yaw), cy = std::cos(joints.yaw);
  const double l = joints.insertion;
  Eigen::Matrix<double, 3, 4> local;
  // Columns: d(l d)/d pitch, d(l d)/d yaw, d, and zero for roll; d as in the header.
  local.col(0) << -l * sp * sy, -l * cp, -l * sp * cy;
  local.col(1) << l * cp * cy, 0.0, -l * cp * sy;
  local.col(2) << cp * sy, -sp, cp * cy;
  local.col(3).setZero();
  return portal_orientation_.toRotationMatrix() * local;
}

ActuatedForces PortalScope::joint_forces(const ScopeJoints& joints, const Vec3& tip_force) const {
  const Eigen::Vector4d tau = jacobian(joints).transpose() * to_eigen(tip_force);
  return {tau[0], tau[1], tau[2]};
}

ScopeJoints PortalScope::clamp(const ScopeJoints& joints) const {
  const ScopeGeometry& g = geometry_;
  ScopeJoints clamped = joints;
  clamped.pitch = std::clamp(joints.pitch, g.min_pitch, g.max_pitch);
  clamped.yaw = std::clamp(joints.yaw, g.min_yaw, g.max_yaw);
  clamped.insertion = std::clamp(joints.insertion, g.min_insertion, g.max_insertion);
  return clamped;
}

bool PortalScope::within_limits(const ScopeJoints& joints) const {
  const ScopeGeometry& g = geometry_;
  return joints.pitch >= g.min_pitch && joints.pitch <= g.max_pitch && joints.yaw >= g.min_yaw &&
         joints.yaw <= g.max_yaw && joints.insertion >= g.min_insertion &&
         joints.insertion <= g.max_insertion;
}

std::string_view describe(ScopeReach reach) {
  switch (reach) {
    case ScopeReach::Ok:
      return "reachable";
    case ScopeReach::TipAtPortal:
      return "tip is at the portal: the shaft direction is undefined";
    case ScopeReach::BehindPortal:
      return "tip is on or behind the portal plane (outside the body)";
    case ScopeReach::PitchOutOfRange:
      return "tip needs a pitch outside the pitch limits";
    case ScopeReach::YawOutOfRange:
      return "tip needs a yaw outside the yaw limits";
    case ScopeReach::InsertionOutOfRange:
      return "tip needs an insertion outside the insertion limits";
  }
  return "unknown";
}

double distance_from_shaft_line(const ScopePose& pose, const Vec3& point) {
  const Vector3d axis = to_eigen(pose.shaft).normalized() * Vector3d::UnitZ();
  return (to_eigen(point) - to_eigen(pose.tip)).cross(axis).norm();
}

// --- PenDevice ---------------------------------------------------------------------------------

PenPose PenDevice::forward(const PenJoints& joints) const {
  return {joints.position, to_quat(yaw_pitch_roll(joints.yaw, joints.pitch, joints.roll))};
}

PenJoints PenDevice::inverse(const PenPose& pose) const {
  // m = Ry(yaw) Rx(pitch) Rz(roll) has row 1 = (cp sin(roll), cp cos(roll), -sin(pitch)) and
  // column 2 = (cp sin(yaw), -sin(pitch), cp cos(yaw)), cp = cos(pitch) >= 0.
  const Matrix3d m = to_eigen(pose.orientation).normalized().toRotationMatrix();
  PenJoints joints;
  joints.position = pose.position;
  joints.pitch = std::atan2(-m(1, 2), std::hypot(m(1, 0), m(1, 1)));
  // At lock both entries of column 2 are rounding noise: put the whole turn in roll.
  joints.yaw = std::hypot(m(0, 2), m(2, 2)) < 1e-12 ? 0.0 : std::atan2(m(0, 2), m(2, 2));
  joints.roll = residual_roll(m, joints.yaw, joints.pitch);
  return joints;
}

PenForces PenDevice::joint_forces(const Vec3& tip_force_n, const Vec3& tip_torque_nm) const {
  return {tip_force_n, tip_torque_nm};
}

// --- StationCalibration ------------------------------------------------------------------------

namespace {

using nlohmann::json;
using namespace json_read;

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

std::string check_mapping(const WorkspaceMapping& m, const std::string& path) {
  if (!std::isfinite(m.scale)) return path + ".scale: must be finite, got " + number(m.scale);
  if (!(m.scale > 0.0)) return path + ".scale: must be > 0, got " + number(m.scale);
  if (auto error = check_unit_quaternion(m.rotation, path + ".rotation"); !error.empty()) {
    return error;
  }
  return check_point(m.offset, path + ".offset");
}

std::string read_vec3(const json& value, const std::string& path, Vec3& out) {
  double v[3];
  if (auto error = read_numbers(value, path, 3, v); !error.empty()) return error;
  out = {v[0], v[1], v[2]};
  return {};
}

std::string read_quat(const json& value, const std::string& path, Quat& out) {
  double q[4];
  if (auto error = read_numbers(value, path, 4, q); !error.empty()) return error;
  out = {q[0], q[1], q[2], q[3]};
  return {};
}

// [min, max] scaled by unit (degrees to radians, or 1 for metres).
std::string read_limits(const json& value, const std::string& path, double unit, double& low,
                        double& high) {
  double v[2];
  if (auto error = read_numbers(value, path, 2, v); !error.empty()) return error;
  low = v[0] * unit;
  high = v[1] * unit;
  return {};
}

std::string require(const json& object, const std::string& path,
                    std::initializer_list<const char*> keys) {
  for (const char* key : keys) {
    if (!object.contains(key)) return path + "." + key + ": missing";
  }
  return {};
}

std::string read_mapping(const json& value, const std::string& path, WorkspaceMapping& mapping) {
  if (!value.is_object()) return wrong_type(path, "an object", value);
  if (auto error = require(value, path, {"scale", "rotation", "offset"}); !error.empty()) {
    return error;
  }
  for (const auto& [key, field] : value.items()) {
    const std::string field_path = path + "." + key;
    std::string error;
    if (key == "scale") {
      error = read_number(field, field_path, mapping.scale);
    } else if (key == "rotation") {
      error = read_quat(field, field_path, mapping.rotation);
    } else if (key == "offset") {
      error = read_vec3(field, field_path, mapping.offset);
    } else {
      error = field_path + ": unknown key (a mapping has scale, rotation and offset)";
    }
    if (!error.empty()) return error;
  }
  return {};
}

std::string read_scope(const json& value, const std::string& path, ScopeGeometry& scope) {
  if (!value.is_object()) return wrong_type(path, "an object", value);
  if (auto error = require(value, path, {"portal", "portal_orientation", "insertion_limits_m"});
      !error.empty()) {
    return error;
  }
  for (const auto& [key, field] : value.items()) {
    const std::string field_path = path + "." + key;
    std::string error;
    if (key == "portal") {
      error = read_vec3(field, field_path, scope.portal);
    } else if (key == "portal_orientation") {
      error = read_quat(field, field_path, scope.portal_orientation);
    } else if (key == "view_angle_deg") {
      error = read_number(field, field_path, scope.view_angle);
      scope.view_angle *= kDegree;
    } else if (key == "field_of_view_deg") {
      error = read_number(field, field_path, scope.field_of_view);
      scope.field_of_view *= kDegree;
    } else if (key == "insertion_limits_m") {
      error = read_limits(field, field_path, 1.0, scope.min_insertion, scope.max_insertion);
    } else if (key == "pitch_limits_deg") {
      error = read_limits(field, field_path, kDegree, scope.min_pitch, scope.max_pitch);
    } else if (key == "yaw_limits_deg") {
      error = read_limits(field, field_path, kDegree, scope.min_yaw, scope.max_yaw);
    } else {
      error = field_path +
              ": unknown key (a scope has portal, portal_orientation, view_angle_deg, "
              "field_of_view_deg, insertion_limits_m, pitch_limits_deg and yaw_limits_deg)";
    }
    if (!error.empty()) return error;
  }
  return {};
}

std::string read_device(const json& value, const std::string& path, DeviceCalibration& device) {
  if (!value.is_object()) return wrong_type(path, "an object", value);
  if (auto error = require(value, path, {"index", "kind", "mapping"}); !error.empty()) {
    return error;
  }
  for (const auto& [key, field] : value.items()) {
    const std::string field_path = path + "." + key;
    std::string error;
    if (key == "index") {
      if (!field.is_number()) {
        error = wrong_type(field_path, "0 or 1", field);
      } else if (field != 0 && field != 1) {
        error = field_path + ": must be 0 or 1, got " + field.dump();
      } else {
        device.index = field.get<int>();
      }
    } else if (key == "kind") {
      if (field == "pen") {
        device.kind = DeviceKind::Pen;
      } else if (field == "scope") {
        device.kind = DeviceKind::Scope;
      } else {
        error = field_path + R"(: must be "pen" or "scope", got )" + field.dump();
      }
    } else if (key == "mapping") {
      error = read_mapping(field, field_path, device.mapping);
    } else if (key != "scope") {  // read below, once the kind is known
      error = field_path + ": unknown key (a device has index, kind, mapping and scope)";
    }
    if (!error.empty()) return error;
  }
  const bool has_scope = value.contains("scope");
  if (device.kind == DeviceKind::Pen) {
    if (!has_scope) return {};
    return path + ".scope: only a scope device has scope geometry, this one is a pen";
  }
  if (!has_scope) return path + ".scope: missing (a scope device needs its geometry)";
  return read_scope(value["scope"], path + ".scope", device.scope);
}

std::string read_station(const json& root, StationCalibration& calibration) {
  if (!root.is_object()) return wrong_type("(calibration)", "an object", root);
  if (!root.contains("devices")) return "devices: missing";
  for (const auto& [key, value] : root.items()) {
    if (key != "devices") return key + ": unknown key (a calibration has devices)";
    if (!value.is_array()) return wrong_type(key, "an array", value);
    // Checked here too, so that a long list is refused before it is read.
    if (value.size() > kMaxStationDevices) {
      return "devices: at most " + std::to_string(kMaxStationDevices) + " devices, got " +
             std::to_string(value.size());
    }
    calibration.devices.resize(value.size());
    for (std::size_t i = 0; i < value.size(); ++i) {
      if (auto error = read_device(value[i], index_path(key, i), calibration.devices[i]);
          !error.empty()) {
        return error;
      }
    }
  }
  return {};
}

json to_json(const Vec3& v) {
  return json::array({v.x, v.y, v.z});
}
json to_json(const Quat& q) {
  return json::array({q.w, q.x, q.y, q.z});
}

}  // namespace

std::string check_scope_geometry(const ScopeGeometry& g, const std::string& path) {
  if (auto error = check_point(g.portal, path + "portal"); !error.empty()) return error;
  if (auto error = check_unit_quaternion(g.portal_orientation, path + "portal_orientation");
      !error.empty()) {
    return error;
  }
  if (!(g.view_angle >= 0.0 && g.view_angle < kMaxViewAngle)) {
    return path + "view_angle_deg: must be in [0, " + number(kMaxViewAngle / kDegree) + "), got " +
           number(g.view_angle / kDegree);
  }
  if (!(g.field_of_view >= kMinFieldOfView && g.field_of_view <= kMaxFieldOfView)) {
    return path + "field_of_view_deg: must be in [" + number(kMinFieldOfView / kDegree) + ", " +
           number(kMaxFieldOfView / kDegree) + "], got " + number(g.field_of_view / kDegree);
  }
  if (!(finite({g.min_insertion, g.max_insertion}) && 0.0 <= g.min_insertion &&
        g.min_insertion < g.max_insertion)) {
    return path + "insertion_limits_m: must satisfy 0 <= min < max, got " +
           numbers({g.min_insertion, g.max_insertion});
  }
  if (auto error = check_angle_limits(g.min_pitch, g.max_pitch, path + "pitch_limits_deg");
      !error.empty()) {
    return error;
  }
  return check_angle_limits(g.min_yaw, g.max_yaw, path + "yaw_limits_deg");
}

const DeviceCalibration* StationCalibration::find(int device_index) const {
  for (const DeviceCalibration& device : devices) {
    if (device.index == device_index) return &device;
  }
  return nullptr;
}

StationCalibration default_station_calibration() {
  StationCalibration calibration;
  calibration.devices.resize(2);
  calibration.devices[1].index = 1;
  return calibration;
}

std::string check_station_calibration(const StationCalibration& calibration) {
  const auto& devices = calibration.devices;
  if (devices.empty()) return "devices: must list at least one device";
  if (devices.size() > kMaxStationDevices) {
    return "devices: at most " + std::to_string(kMaxStationDevices) + " devices, got " +
           std::to_string(devices.size());
  }
  for (std::size_t i = 0; i < devices.size(); ++i) {
    const DeviceCalibration& device = devices[i];
    const std::string path = index_path("devices", i);
    if (device.index != 0 && device.index != 1) {
      return path + ".index: must be 0 or 1, got " + std::to_string(device.index);
    }
    for (std::size_t earlier = 0; earlier < i; ++earlier) {
      if (devices[earlier].index == device.index) {
        return path + ".index: device " + std::to_string(device.index) +
               " is already calibrated by " + index_path("devices", earlier);
      }
    }
    if (auto error = check_mapping(device.mapping, path + ".mapping"); !error.empty()) {
      return error;
    }
    if (device.kind == DeviceKind::Scope) {
      if (auto error = check_scope_geometry(device.scope, path + ".scope."); !error.empty()) {
        return error;
      }
    }
  }
  return {};
}

ParseResult<StationCalibration> parse_station_calibration(std::string_view json_text) {
  using Result = ParseResult<StationCalibration>;
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::exception& e) {
    // A syntax error, or a number too large for a double (out_of_range 406). Drop nlohmann's
    // "[json.exception.parse_error.101] " prefix; keep line, column and cause.
    const std::string what = e.what();
    const auto cut = what.find("] ");
    return Result::failure("not valid JSON: " +
                           (cut == std::string::npos ? what : what.substr(cut + 2)));
  }
  StationCalibration calibration;
  std::string error = read_station(root, calibration);
  if (error.empty()) error = check_station_calibration(calibration);
  if (!error.empty()) return Result::failure(std::move(error));
  for (DeviceCalibration& device : calibration.devices) {
    device.mapping.rotation = to_quat(to_eigen(device.mapping.rotation).normalized());
    device.scope.portal_orientation =
        to_quat(to_eigen(device.scope.portal_orientation).normalized());
  }
  return Result::success(std::move(calibration));
}

std::string station_calibration_json(const StationCalibration& calibration) {
  json devices = json::array();
  for (const DeviceCalibration& device : calibration.devices) {
    json entry = {
        {"index", device.index},
        {"kind", device.kind == DeviceKind::Scope ? "scope" : "pen"},
        {"mapping",
         {{"scale", device.mapping.scale},
          {"rotation", to_json(device.mapping.rotation)},
          {"offset", to_json(device.mapping.offset)}}},
    };
    if (device.kind == DeviceKind::Scope) {
      const ScopeGeometry& s = device.scope;
      entry["scope"] = {
          {"portal", to_json(s.portal)},
          {"portal_orientation", to_json(s.portal_orientation)},
          {"view_angle_deg", s.view_angle / kDegree},
          {"field_of_view_deg", s.field_of_view / kDegree},
          {"insertion_limits_m", {s.min_insertion, s.max_insertion}},
          {"pitch_limits_deg", {s.min_pitch / kDegree, s.max_pitch / kDegree}},
          {"yaw_limits_deg", {s.min_yaw / kDegree, s.max_yaw / kDegree}},
      };
    }
    devices.push_back(std::move(entry));
  }
  return json{{"devices", std::move(devices)}}.dump();
}

}  // namespace incise::devices
