#include "curriculum/motion_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "curriculum/number_text.h"

namespace incise::curriculum {

namespace {

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kJawClosedBelow = 0.5;  // jaw <= this counts as closed

Vec3 minus(const Vec3& a, const Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec3 scaled(const Vec3& a, double s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}
double norm(const Vec3& v) {
  return std::hypot(v[0], v[1], v[2]);
}
double norm(const Quat& q) {
  return std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
}

template <std::size_t N>
bool all_finite(const std::array<double, N>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

[[noreturn]] void bad_sample(std::string_view hand, std::size_t index, std::string_view reason) {
  std::ostringstream message;
  message << hand << "sample " << index << ": " << reason;
  throw std::invalid_argument(message.str());
}

void check_threshold(std::string_view name, double value) {
  if (!std::isfinite(value))
    throw std::invalid_argument("thresholds: " + std::string(name) + " is not finite");
  if (value < 0)
    throw std::invalid_argument("thresholds: " + std::string(name) + " " + shortest_text(value) +
                                " is negative");
}

void check_thresholds(const MotionThresholds& th) {
  check_threshold("moving_speed_m_s", th.moving_speed_m_s);
  check_threshold("still_speed_m_s", th.still_speed_m_s);
  check_threshold("min_idle_s", th.min_idle_s);
  check_threshold("smoothing_s", th.smoothing_s);
  // Without this the hysteresis would re-arm while the hand is still moving.
  if (th.still_speed_m_s > th.moving_speed_m_s)
    throw std::invalid_argument("thresholds: still_speed_m_s " + shortest_text(th.still_speed_m_s) +
                                " is above moving_speed_m_s " + shortest_text(th.moving_speed_m_s));
}

// Checked before any arithmetic, so that a NaN cannot hide inside a max or a sum. #hand is "" or
// "right " / "left ", prefixed to the message.
void check_samples(std::span<const HandSample> samples, std::string_view hand) {
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const HandSample& s = samples[i];
    if (!std::isfinite(s.t_s)) bad_sample(hand, i, "t_s is not finite");
    if (!all_finite(s.tip_m)) bad_sample(hand, i, "tip_m is not finite");
    if (!all_finite(s.orientation)) bad_sample(hand, i, "orientation is not finite");
    if (!std::isfinite(s.jaw)) bad_sample(hand, i, "jaw is not finite");
    if (!all_finite(s.force_n)) bad_sample(hand, i, "force_n is not finite");
    if (i > 0 && s.t_s < samples[i - 1].t_s)
      bad_sample(hand, i,
                 "t_s " + shortest_text(s.t_s) + " is before the previous sample's " +
                     shortest_text(samples[i - 1].t_s));
    const double q_norm = norm(s.orientation);
    if (std::abs(q_norm - 1) > kUnitQuaternionTolerance)
      bad_sample(hand, i,
                 "orientation is not a unit quaternion (norm " + shortest_text(q_norm) + ")");
    if (s.jaw < 0 || s.jaw > 1)
      bad_sample(hand, i, "jaw " + shortest_text(s.jaw) + " is outside [0, 1]");
  }
}

// Rotation angle between two orientations [rad], in [0, pi]. Equal to 2 acos |<a, b>| for unit
// quaternions, but through atan2 of the relative rotation conj(a) b, which keeps full precision for
// the tiny angles between consecutive ticks (acos loses half the digits near 1).
double rotation_angle(const Quat& a_in, const Quat& b_in) {
  const double na = norm(a_in);
  const double nb = norm(b_in);
  const Quat a = {a_in[0] / na, a_in[1] / na, a_in[2] / na, a_in[3] / na};
  const Quat b = {b_in[0] / nb, b_in[1] / nb, b_in[2] / nb, b_in[3] / nb};
  const double w = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  const Vec3 v = {a[0] * b[1] - b[0] * a[1] - (a[2] * b[3] - a[3] * b[2]),
                  a[0] * b[2] - b[0] * a[2] - (a[3] * b[1] - a[1] * b[3]),
                  a[0] * b[3] - b[0] * a[3] - (a[1] * b[2] - a[2] * b[1])};
  return 2 * std::atan2(norm(v), std::abs(w));
}

// The tip's path sampled at strictly increasing times: of samples sharing a time the last is kept,
// since a time derivative across no time is undefined.
struct Trajectory {
  std::vector<double> t;
  std::vector<Vec3> x;
};

Trajectory distinct_times(std::span<const HandSample> hand) {
  Trajectory path;
  path.t.reserve(hand.size());
  path.x.reserve(hand.size());
  for (std::size_t i = 0; i < hand.size(); ++i) {
    if (i + 1 < hand.size() && hand[i + 1].t_s == hand[i].t_s) continue;
    path.t.push_back(hand[i].t_s);
    path.x.push_back(hand[i].tip_m);
  }
  return path;
}

// Central-difference velocity at sample k, one-sided at the ends; zero for a single sample.
Vec3 velocity(const Trajectory& path, std::size_t k) {
  const std::size_t m = path.t.size();
  if (m < 2) return {};
  const std::size_t lo = k == 0 ? 0 : k - 1;
  const std::size_t hi = k + 1 == m ? k : k + 1;
  return scaled(minus(path.x[hi], path.x[lo]), 1 / (path.t[hi] - path.t[lo]));
}

std::vector<double> raw_speeds(const Trajectory& path) {
  std::vector<double> speeds(path.t.size());
  for (std::size_t k = 0; k < speeds.size(); ++k)
    speeds[k] = norm(velocity(path, k));
  return speeds;
}

// The time average of the piecewise-linear speed over a window of #width centred on each sample,
// clipped to the run: a prefix integral and two pointers that only move forward, so O(samples).
std::vector<double> smoothed_speeds(const std::vector<double>& t, const std::vector<double>& s,
                                    double width) {
  const std::size_t m = t.size();
  std::vector<double> prefix(m, 0.0);  // integral of the speed from t[0] to t[k] [m]
  for (std::size_t k = 1; k < m; ++k)
    prefix[k] = prefix[k - 1] + 0.5 * (t[k] - t[k - 1]) * (s[k - 1] + s[k]);

  // Integral from t[0] to #time, with #segment the last sample at or before #time.
  const auto integral_to = [&](double time, std::size_t& segment) {
    while (segment + 1 < m && t[segment + 1] <= time)
      ++segment;
    if (segment + 1 == m) return prefix[segment];
    const double u = time - t[segment];
    const double s_at =
        s[segment] + (s[segment + 1] - s[segment]) * u / (t[segment + 1] - t[segment]);
    return prefix[segment] + 0.5 * u * (s[segment] + s_at);
  };

  std::vector<double> smoothed(m);
  std::size_t lo_segment = 0;
  std::size_t hi_segment = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const double a = std::max(t.front(), t[k] - 0.5 * width);
    const double b = std::min(t.back(), t[k] + 0.5 * width);
    if (b > a) {
      const double integral_b = integral_to(b, hi_segment);
      smoothed[k] = (integral_b - integral_to(a, lo_segment)) / (b - a);
    } else {
      smoothed[k] = s[k];
    }
  }
  return smoothed;
}

// The time each sample stands for: halfway to its neighbours, the run's ends for the first and
// last, so that the durations sum to the run's.
std::vector<double> sample_durations(const std::vector<double>& t) {
  const std::size_t m = t.size();
  std::vector<double> durations(m, 0.0);
  for (std::size_t k = 0; k < m; ++k) {
    const double from = k == 0 ? t[0] : 0.5 * (t[k - 1] + t[k]);
    const double to = k + 1 == m ? t[m - 1] : 0.5 * (t[k] + t[k + 1]);
    durations[k] = to - from;
  }
  return durations;
}

// Integral of |jerk|^2 dt with the staggered differences documented in the header. Needs >= 4
// samples.
double squared_jerk_integral(const Trajectory& path) {
  const std::size_t m = path.t.size();
  const auto& t = path.t;
  std::vector<Vec3> v(m - 1);  // at tv[i] = (t[i] + t[i+1]) / 2
  std::vector<double> tv(m - 1);
  for (std::size_t i = 0; i + 1 < m; ++i) {
    v[i] = scaled(minus(path.x[i + 1], path.x[i]), 1 / (t[i + 1] - t[i]));
    tv[i] = 0.5 * (t[i] + t[i + 1]);
  }
  std::vector<Vec3> a(m - 2);
  std::vector<double> ta(m - 2);
  for (std::size_t i = 0; i + 1 < v.size(); ++i) {
    a[i] = scaled(minus(v[i + 1], v[i]), 1 / (tv[i + 1] - tv[i]));
    ta[i] = 0.5 * (tv[i] + tv[i + 1]);
  }
  // Jerk i sits at tj(i); it stands for the time halfway to its neighbours, the first and last
  // ones extended to the run's ends.
  const std::size_t n_jerk = m - 3;
  const auto tj = [&](std::size_t i) { return 0.5 * (ta[i] + ta[i + 1]); };
  double integral = 0;
  double cell_start = t.front();
  for (std::size_t i = 0; i < n_jerk; ++i) {
    const double jerk = norm(minus(a[i + 1], a[i])) / (ta[i + 1] - ta[i]);
    const double cell_end = i + 1 < n_jerk ? 0.5 * (tj(i) + tj(i + 1)) : t.back();
    integral += jerk * jerk * (cell_end - cell_start);
    cell_start = cell_end;
  }
  return integral;
}

double log_dimensionless_jerk(const Trajectory& path, const std::vector<double>& speeds) {
  if (path.t.size() < 4) return kNaN;
  const double peak_speed = *std::max_element(speeds.begin(), speeds.end());
  if (peak_speed == 0) return kNaN;
  const double duration = path.t.back() - path.t.front();
  return -std::log(duration * duration * duration / (peak_speed * peak_speed) *
                   squared_jerk_integral(path));
}

double path_length(std::span<const HandSample> hand) {
  double length = 0;
  for (std::size_t i = 1; i < hand.size(); ++i)
    length += norm(minus(hand[i].tip_m, hand[i - 1].tip_m));
  return length;
}

// The speed-derived state of one hand on its distinct sample times.
struct SpeedProfile {
  Trajectory path;
  std::vector<double> raw;        // central-difference speed [m/s]
  std::vector<double> smoothed;   // [m/s]
  std::vector<double> durations;  // [s]
};

SpeedProfile speed_profile(std::span<const HandSample> hand, const MotionThresholds& th) {
  SpeedProfile profile;
  profile.path = distinct_times(hand);
  profile.raw = raw_speeds(profile.path);
  profile.smoothed = smoothed_speeds(profile.path.t, profile.raw, th.smoothing_s);
  profile.durations = sample_durations(profile.path.t);
  return profile;
}

}  // namespace

std::vector<MetricValue> hand_metrics(std::span<const HandSample> hand,
                                      const MotionThresholds& thresholds) {
  check_thresholds(thresholds);
  check_samples(hand, "");

  const double length = path_length(hand);
  double angular_path = 0;
  double peak_force = 0;
  double force_integral = 0;          // [N s]
  double force_squared_integral = 0;  // [N^2 s]
  double jaw_closures = 0;
  for (std::size_t i = 0; i < hand.size(); ++i) {
    const double force = norm(hand[i].force_n);
    peak_force = std::max(peak_force, force);
    if (i == 0) continue;
    const HandSample& previous = hand[i - 1];
    angular_path += rotation_angle(previous.orientation, hand[i].orientation);
    const double dt = hand[i].t_s - previous.t_s;
    const double previous_force = norm(previous.force_n);
    force_integral += 0.5 * dt * (previous_force + force);
    force_squared_integral += 0.5 * dt * (previous_force * previous_force + force * force);
    if (previous.jaw > kJawClosedBelow && hand[i].jaw <= kJawClosedBelow) ++jaw_closures;
  }
  const double duration = hand.size() < 2 ? 0.0 : hand.back().t_s - hand.front().t_s;
  const double straight = hand.empty() ? 0.0 : norm(minus(hand.back().tip_m, hand.front().tip_m));
  // min() because rounding can make a straight line's summed steps a hair shorter than its chord.
  const double economy = length > 0 ? std::min(1.0, straight / length) : 0.0;

  const SpeedProfile profile = speed_profile(hand, thresholds);
  double movements = 0;
  bool armed = true;  // the hand is still before the run starts
  double idle_time = 0;
  double still_stretch = 0;  // duration of the current run of still samples [s]
  for (std::size_t k = 0; k < profile.smoothed.size(); ++k) {
    const double speed = profile.smoothed[k];
    if (armed && speed > thresholds.moving_speed_m_s) {
      ++movements;
      armed = false;
    } else if (speed < thresholds.still_speed_m_s) {
      armed = true;
    }
    if (speed < thresholds.still_speed_m_s) {
      still_stretch += profile.durations[k];
    } else {
      if (still_stretch >= thresholds.min_idle_s) idle_time += still_stretch;
      still_stretch = 0;
    }
  }
  if (still_stretch >= thresholds.min_idle_s) idle_time += still_stretch;

  return {
      {"path_length_m", length, "m"},
      {"angular_path_rad", angular_path, "rad"},
      {"economy_of_motion", economy, ""},
      {"movements", movements, "count"},
      {"idle_time_s", idle_time, "s"},
      {"mean_speed_m_s", duration > 0 ? length / duration : 0.0, "m/s"},
      {"log_dimensionless_jerk", log_dimensionless_jerk(profile.path, profile.raw), ""},
      {"peak_force_n", peak_force, "N"},
      {"rms_force_n", duration > 0 ? std::sqrt(force_squared_integral / duration) : 0.0, "N"},
      {"integrated_force_ns", force_integral, "N s"},
      {"jaw_closures", jaw_closures, "count"},
  };
}

void check_hand_samples(std::span<const HandSample> right, std::span<const HandSample> left,
                        bool two_handed) {
  if (!two_handed) {
    check_samples(right, "");
    return;
  }
  check_samples(right, "right ");
  check_samples(left, "left ");
  if (right.size() != left.size())
    throw std::invalid_argument("right has " + std::to_string(right.size()) +
                                " samples but left has " + std::to_string(left.size()));
  for (std::size_t i = 0; i < right.size(); ++i)
    if (left[i].t_s != right[i].t_s)
      bad_sample("", i,
                 "left t_s " + shortest_text(left[i].t_s) + " differs from right t_s " +
                     shortest_text(right[i].t_s));
}

std::vector<MetricValue> bimanual_metrics(std::span<const HandSample> right,
                                          std::span<const HandSample> left,
                                          const MotionThresholds& thresholds) {
  check_thresholds(thresholds);
  check_hand_samples(right, left, true);

  // Aligned times give both hands the same distinct times and sample durations.
  const SpeedProfile r = speed_profile(right, thresholds);
  const SpeedProfile l = speed_profile(left, thresholds);
  double both_moving = 0;
  double either_moving = 0;
  for (std::size_t k = 0; k < r.smoothed.size(); ++k) {
    const bool right_moves = r.smoothed[k] > thresholds.moving_speed_m_s;
    const bool left_moves = l.smoothed[k] > thresholds.moving_speed_m_s;
    if (right_moves && left_moves) both_moving += r.durations[k];
    if (right_moves || left_moves) either_moving += r.durations[k];
  }
  const double right_length = path_length(right);

  return {
      {"bimanual_dexterity", either_moving > 0 ? both_moving / either_moving : 0.0, ""},
      {"path_length_ratio", right_length > 0 ? path_length(left) / right_length : kNaN, ""},
  };
}

}  // namespace incise::curriculum
