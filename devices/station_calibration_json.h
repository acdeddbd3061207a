#pragma once
// A station's calibration as the JSON text the database stores and the welcome message carries
// (the format is in station_calibration.h). Part of the station kinematics (kinematics.h).

#include <string>
#include <string_view>

#include "devices/parse_result.h"
#include "devices/station_calibration.h"

namespace incise::devices {

// Errors as check_station_calibration's, or `not valid JSON: ...`, or a type error such as
// `devices[0].mapping.offset[2]: must be a number, got string`.
ParseResult<StationCalibration> parse_station_calibration(std::string_view json_text);

// The format of station_calibration.h, compact. Numbers are printed in full precision; angles are
// stored in degrees, so they read back within a rounding error (~1e-16 relative).
std::string station_calibration_json(const StationCalibration& calibration);

}  // namespace incise::devices
