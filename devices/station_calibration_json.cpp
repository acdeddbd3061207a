// A station's calibration to and from its stored JSON.
#include "devices/station_calibration_json.h"

#include <initializer_list>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "devices/eigen_conversions.h"
#include "devices/json_read.h"
#include "devices/protocol.h"

namespace incise::devices {
namespace {

using nlohmann::json;
using namespace json_read;

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
