// A station's calibration: the default, the lookup by device, and the rules a calibration must
// meet.
#include "devices/station_calibration.h"

#include <cmath>
#include <string>

#include "devices/calibration_checks.h"
#include "devices/json_read.h"
#include "devices/protocol.h"

namespace incise::devices {
namespace {

using json_read::index_path;

std::string check_mapping(const WorkspaceMapping& m, const std::string& path) {
  if (!std::isfinite(m.scale)) return path + ".scale: must be finite, got " + number(m.scale);
  if (!(m.scale > 0.0)) return path + ".scale: must be > 0, got " + number(m.scale);
  if (auto error = check_unit_quaternion(m.rotation, path + ".rotation"); !error.empty()) {
    return error;
  }
  return check_point(m.offset, path + ".offset");
}

}  // namespace

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

}  // namespace incise::devices
