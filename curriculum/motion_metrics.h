#pragma once
// Motion and force metrics of one or two hands (haptic devices) over a recorded attempt: how far
// and how smoothly the tool moved, how often it stopped, how hard it pressed, and how the two hands
// worked together. Pure functions over plain sample streams, like metrics.h.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "curriculum/metrics.h"

namespace incise::curriculum {

// One hand (device) at one simulation tick.
struct HandSample {
  double t_s = 0;                                 // since the start of the run [s], non-decreasing
  std::array<double, 3> tip_m{};                  // tool tip position [m]
  std::array<double, 4> orientation{1, 0, 0, 0};  // tool orientation, unit quaternion w, x, y, z
  double jaw = 0;                                 // jaw opening, 0 closed .. 1 open
  std::array<double, 3> force_n{};                // force on the tool [N]
  std::uint8_t buttons = 0;                       // bit i set = button i pressed
};

// How the speed of the tip is turned into "moving" and "still".
struct MotionThresholds {
  double moving_speed_m_s = 0.01;  // a movement starts when the smoothed speed rises above this
  double still_speed_m_s = 0.005;  // ... after having been below this (hysteresis); also "idle"
  double min_idle_s = 0.2;         // shorter still stretches are not idle time
  double smoothing_s = 0.02;       // width of the moving average applied to the speed [s]
};

// A quaternion counts as unit when its norm is within this of 1.
inline constexpr double kUnitQuaternionTolerance = 1e-3;

// The eleven metrics of one hand over #hand, in this order:
//   path_length_m           sum over i of |tip_{i+1} - tip_i| [m]
//   angular_path_rad        sum over i of the rotation angle from orientation_i to
//   orientation_{i+1},
//                           2 acos |<q_i, q_{i+1}>| (of the normalised quaternions) [rad]
//   economy_of_motion       |tip_last - tip_first| / path length, in [0, 1]; 0 when there is no
//   path movements               number of times the smoothed speed rises above moving_speed_m_s
//   after
//                           having been below still_speed_m_s; the hand counts as still before the
//                           first sample, so a run that starts moving counts that movement
//   idle_time_s             total duration of the stretches of at least min_idle_s during which the
//                           smoothed speed is below still_speed_m_s [s]
//   mean_speed_m_s          path length / duration [m/s]; 0 when the run has no duration
//   log_dimensionless_jerk  LDLJ = -ln(T^3 / v_peak^2 * integral of |d^2 v / dt^2|^2 dt), T the
//                           duration (Balasubramanian et al. 2015); higher (less negative) is
//                           smoother; NaN when the tip never moves or there are fewer than 4
//                           distinct sample times (undefined; NaN fails every threshold), +infinity
//                           for a motion without jerk (constant velocity)
//   peak_force_n            max over i of |force_i| [N]
//   rms_force_n             sqrt(integral of |force|^2 dt / duration), trapezoid rule, as in
//                           basic_metrics [N]; 0 when the run has no duration
//   integrated_force_ns     integral of |force| dt, trapezoid rule [N s]
//   jaw_closures            number of i with jaw_i > 0.5 and jaw_{i+1} <= 0.5
//
// Discretisation. Samples sharing a time with the next sample are skipped by the time derivatives
// (the last one at each time is kept); path, rotation, force and jaw use every sample.
// - Speed (movements, idle time, bimanual): the velocity at sample i is the central difference
//   (tip_{i+1} - tip_{i-1}) / (t_{i+1} - t_{i-1}), one-sided at the first and last sample. The
//   speed is taken as piecewise linear between samples and smoothed by its time average over
//   [t_i - smoothing_s / 2, t_i + smoothing_s / 2] clipped to the run (smoothing_s = 0: no
//   smoothing). Time-averaging keeps the result independent of the sampling rate.
// - Durations: sample i stands for the time from halfway to its previous sample to halfway to its
//   next (the run's ends for the first and last sample), so these durations sum to the run's.
// - Jerk: velocities v_{i+1/2} = (tip_{i+1} - tip_i) / (t_{i+1} - t_i) at the interval midpoints,
//   accelerations by differencing those at the midpoints of consecutive midpoints, and jerks by
//   differencing those again (for uniform sampling: (x_{i+2} - 3 x_{i+1} + 3 x_i - x_{i-1}) / dt^3
//   at t_{i+1/2}). The integral of |jerk|^2 gives each jerk sample the time halfway to its
//   neighbours, the first and last ones extended to the run's ends. v_peak is the largest
//   central-difference speed (unsmoothed).
//
// Throws std::invalid_argument for bad thresholds (negative or non-finite values, still speed above
// moving speed), and for a non-finite value, a time smaller than the previous sample's, a jaw
// outside [0, 1] or an orientation whose norm differs from 1 by more than
// kUnitQuaternionTolerance, naming the sample index, e.g.
// "sample 7: t_s 0.012 is before the previous sample's 0.014".
std::vector<MetricValue> hand_metrics(std::span<const HandSample> hand,
                                      const MotionThresholds& thresholds = {});

// The two metrics of a two-handed run, in this order:
//   bimanual_dexterity  time during which both hands move / time during which either moves, where
//                       a hand moves while its smoothed speed is above moving_speed_m_s (speed and
//                       durations as in hand_metrics); in [0, 1]; 0 when neither hand moves
//   path_length_ratio   path length of the left (non-dominant) hand / path length of the right
//                       (dominant) hand; NaN when the right hand has no path
// #right and #left must be sample-aligned: the same number of samples with the same t_s at each
// index. Throws std::invalid_argument otherwise (e.g. "sample 4: left t_s 0.01 differs from right
// t_s 0.008"), and for bad samples or thresholds as hand_metrics does, with the message prefixed
// by the hand ("right sample 7: ...").
std::vector<MetricValue> bimanual_metrics(std::span<const HandSample> right,
                                          std::span<const HandSample> left,
                                          const MotionThresholds& thresholds = {});

// The sample checks of hand_metrics (one hand: #right, messages without a hand prefix; #left is
// ignored) or of bimanual_metrics (two hands: each hand's samples, then their alignment), with the
// same messages: every metric over the same recording refuses it in the same words.
void check_hand_samples(std::span<const HandSample> right, std::span<const HandSample> left,
                        bool two_handed);

}  // namespace incise::curriculum
