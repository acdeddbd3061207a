#pragma once
// A station's calibration: per device its kind, workspace mapping and scope geometry, with the
// rules a stored one must meet (its JSON: station_calibration_json.h). Part of the station
// kinematics (kinematics.h).

#include <string>
#include <vector>

#include "devices/portal_scope.h"
#include "devices/workspace_mapping.h"

namespace incise::devices {

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

}  // namespace incise::devices
