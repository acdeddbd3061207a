#pragma once
// Device kinematics of a haptic station: how each device's readings become a tool pose in the
// scene, and how a scene force becomes what the device's motors render.
//
//   WorkspaceMapping    device frame -> scene frame (scale, rotation, offset) and forces back
//                       (workspace_mapping.h)
//   PortalScope         4-DOF arthroscope/laparoscope pivoting about a fulcrum at the portal:
//                       pitch, yaw, insertion (actuated) and roll (free), 30-degree optics
//                       (portal_scope.h)
//   PenDevice           6-DOF pen (Phantom-like): 3 actuated translations + a passive gimbal
//                       (pen_device.h)
//   StationCalibration  per-device kind, mapping and scope geometry (station_calibration.h),
//                       stored as JSON (station_calibration_json.h)
//
// Units: metres, radians, newtons, newton-metres. Values cross this interface as the plain
// devices::Vec3 / Quat of the wire protocol; Eigen is used inside and for the Jacobian.
// Nothing here allocates except the calibration functions and the PortalScope constructor's
// check, so the kinematics may run in the 1 kHz haptic loop.
//
// This header includes them all.

#include "devices/eigen_conversions.h"
#include "devices/pen_device.h"
#include "devices/portal_scope.h"
#include "devices/station_calibration.h"
#include "devices/station_calibration_json.h"
#include "devices/workspace_mapping.h"
