#pragma once
// Force-displacement data for calibration (docs/calibration.md): a probe pushes on the tissue at
// one or more contact points and the tip's position is recorded over time, the form of an
// indentation experiment and of seed 004's cube test. As CSV, one row per sample, a header naming
// the columns (any order; other columns are ignored):
//   time_s                     sample time [s]
//   contact                    which contact point (an integer): each is its own experiment
//   x, y, z                    the probe tip's position [m]
//   dir_x, dir_y, dir_z        the direction the probe pushes (normalised on reading)
//   force_n                    the force along that direction [N]
// Within a contact, times increase with one step between samples (the same for every contact).
// The tissue is at rest at a contact's first sample, whose position is where the probe touches;
// sample k's force acts from sample k-1 to sample k.

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "sim/core/types.h"

namespace incise::sim::calibrate {

// A data file or a scene the calibration cannot use; what() is one line saying where and why
// ("line 7: force_n 'abc' is not a number").
class CalibrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ProbeSample {
  Real time = 0;                   // [s]
  Vec3 position = Vec3::Zero();    // [m]
  Vec3 direction = Vec3::UnitZ();  // unit
  Real force = 0;                  // [N] along direction
};

struct ProbeContact {
  int id = 0;                        // the CSV's contact value
  std::vector<ProbeSample> samples;  // increasing time, evenly spaced
};

struct ProbeData {
  std::vector<ProbeContact> contacts;  // by increasing id
  Real step = 0;                       // time between samples [s], the same for all contacts
};

// Fewer samples than this per contact cannot tell stiffness from noise.
inline constexpr int kMinSamplesPerContact = 5;
// Spacing within this fraction of the first step counts as even.
inline constexpr Real kStepTolerance = 0.01;
// The step between samples [s]: from a haptic device's rate to a slow indentation's.
inline constexpr Real kMinStep = 1e-6;
inline constexpr Real kMaxStep = 10;

// Parses and checks the CSV text. Throws CalibrationError for a control character (a NUL, ...),
// a missing column, a value that is not a finite number, a contact that is not an integer, a
// zero direction, a negative force, too few samples, times that do not increase evenly or a step
// outside [kMinStep, kMaxStep], or a contact with no force at all (no contact). Never throws
// anything else.
ProbeData parse_probe_csv(std::string_view text);

// The CSV text of data (a header and one row per sample, full precision): parse_probe_csv reads
// it back exactly.
std::string probe_csv(const ProbeData& data);

}  // namespace incise::sim::calibrate
