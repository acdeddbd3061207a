#include "sim/tools/grasper.h"

#include <algorithm>
#include <cmath>
#include <concepts>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/collide/triangle_geometry.h"

namespace incise::sim::tools {
namespace {

std::string number(Real value) {
  return std::to_string(value);
}

void require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument(message);
}

// The per-step checks (measure, prescribe, hold) build their message only when they fail: a
// step must not allocate (tests/sim/surgery/surgical_scene_allocation_test.cpp).
template <std::invocable Message>
void require(bool ok, Message&& message) {
  if (!ok) throw std::invalid_argument(message());
}

void check_settings(const GraspSettings& s) {
  require(s.jaw_length > 0 && std::isfinite(s.jaw_length),
          "Grasper: jaw_length must be finite and > 0, got " + number(s.jaw_length));
  require(s.jaw_radius > 0 && std::isfinite(s.jaw_radius),
          "Grasper: jaw_radius must be finite and > 0, got " + number(s.jaw_radius));
  require(s.grab_margin >= 0 && std::isfinite(s.grab_margin),
          "Grasper: grab_margin must be finite and >= 0, got " + number(s.grab_margin));
  require(s.reach >= 0 && std::isfinite(s.reach),
          "Grasper: reach must be finite and >= 0, got " + number(s.reach));
  require(s.close_angle >= 0 && s.close_angle < std::numbers::pi,
          "Grasper: close_angle must be in [0, pi), got " + number(s.close_angle));
  require(s.open_angle >= s.close_angle && s.open_angle < std::numbers::pi,
          "Grasper: open_angle must be in [close_angle, pi), got " + number(s.open_angle) +
              " with close_angle " + number(s.close_angle));
  require(s.tear_force > 0, "Grasper: tear_force must be > 0, got " + number(s.tear_force));
}

}  // namespace

std::string_view to_string(GraspPhase phase) {
  switch (phase) {
    case GraspPhase::open:
      return "open";
    case GraspPhase::closing:
      return "closing";
    case GraspPhase::holding:
      return "holding";
    case GraspPhase::closed_empty:
      return "closed_empty";
  }
  return "unknown";
}

std::string_view to_string(ReleaseReason reason) {
  switch (reason) {
    case ReleaseReason::opened:
      return "opened";
    case ReleaseReason::torn:
      return "torn";
    case ReleaseReason::lost:
      return "lost";
  }
  return "unknown";
}

Grasper::Grasper(GraspSettings settings) : settings_(settings) {
  check_settings(settings_);
}

void Grasper::set_frame(const JawPose& pose) {
  // make_jaw_pair validates the pose and normalises as we do; build it first so that a bad pose
  // leaves the grasper unchanged.
  jaws_ = collide::make_jaw_pair(pose.pivot, pose.direction, pose.opening_normal,
                                 pose.opening_angle, settings_.jaw_length, settings_.jaw_radius);
  const Vec3 d = pose.direction.normalized();
  const Vec3 u = (pose.opening_normal - pose.opening_normal.dot(d) * d).normalized();
  previous_origin_ = origin_;
  previous_rotation_ = rotation_;
  origin_ = pose.pivot;
  rotation_.col(0) = d;
  rotation_.col(1) = u;
  rotation_.col(2) = d.cross(u);
  tips_midpoint_ = 0.5 * (jaws_.jaws[0].b + jaws_.jaws[1].b);
}

std::optional<ReleaseEvent> Grasper::set_jaws(const JawPose& pose) {
  const bool first = !has_pose_;
  set_frame(pose);
  if (first) {
    // No earlier pose: the tool did not move "during" this step.
    previous_origin_ = origin_;
    previous_rotation_ = rotation_;
    has_pose_ = true;
  }
  const Real angle = pose.opening_angle;
  switch (phase_) {
    case GraspPhase::open:
      if (angle <= settings_.close_angle) phase_ = GraspPhase::closing;
      break;
    case GraspPhase::closing:
    case GraspPhase::closed_empty:
      if (angle >= settings_.open_angle) phase_ = GraspPhase::open;
      break;
    case GraspPhase::holding:
      if (angle >= settings_.open_angle) return release(ReleaseReason::opened);
      break;
  }
  return std::nullopt;
}

void Grasper::check_arrays(const Points& rest, const Points& x, const VecX& inverse_masses,
                           std::span<const int> candidates, const char* where) const {
  const Eigen::Index n = x.rows();
  require(rest.rows() == n && inverse_masses.size() == n,
          std::string("Grasper::") + where + ": rest, x and inverse_masses must have the same " +
              "number of rows, got " + std::to_string(rest.rows()) + ", " + std::to_string(n) +
              " and " + std::to_string(inverse_masses.size()));
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    require(candidates[k] >= 0 && candidates[k] < n,
            std::string("Grasper::") + where + ": candidate " + std::to_string(k) + " is vertex " +
                std::to_string(candidates[k]) + ", outside [0, " + std::to_string(n) + ")");
  }
}

std::optional<RestRegion> Grasper::refine_request(const Points& rest, const Points& x,
                                                  const VecX& inverse_masses,
                                                  std::span<const int> candidates) const {
  check_arrays(rest, x, inverse_masses, candidates, "refine_request");
  if (phase_ != GraspPhase::closing) return std::nullopt;
  // The middle of the jaws: the grab region (the jaw triangle widened by radius + margin) and
  // the fallback's reach around the tips are both within half a jaw length plus the larger of
  // the two of it.
  const Vec3 middle = 0.5 * (jaws_.jaws[0].a + tips_midpoint_);
  int nearest = -1;
  Real best = std::numeric_limits<Real>::infinity();
  for (const int i : candidates) {
    if (!(inverse_masses[i] > 0)) continue;
    const Real distance = (row3(x, i) - middle).squaredNorm();
    if (distance < best) {
      best = distance;
      nearest = i;
    }
  }
  if (nearest < 0) return std::nullopt;
  return RestRegion{row3(rest, nearest) + (middle - row3(x, nearest)),
                    0.5 * settings_.jaw_length +
                        std::max(settings_.jaw_radius + settings_.grab_margin, settings_.reach)};
}

int Grasper::grab(const Points& rest, const Points& x, const VecX& inverse_masses,
                  std::span<const int> candidates) {
  if (phase_ != GraspPhase::closing) {
    throw std::logic_error(std::string("Grasper::grab: the jaws must be closing, the phase is ") +
                           std::string(to_string(phase_)));
  }
  check_arrays(rest, x, inverse_masses, candidates, "grab");
  grabbed_.clear();
  const Real reach = settings_.jaw_radius + settings_.grab_margin;
  const Vec3& pivot = jaws_.jaws[0].a;
  const Vec3& tip0 = jaws_.jaws[0].b;
  const Vec3& tip1 = jaws_.jaws[1].b;
  int nearest = -1;
  Real best = std::numeric_limits<Real>::infinity();
  for (const int i : candidates) {
    if (!(inverse_masses[i] > 0)) continue;
    const Vec3 p = row3(x, i);
    const Vec3 w = collide::closest_point_barycentric(p, pivot, tip0, tip1);
    const Vec3 closest = w[0] * pivot + w[1] * tip0 + w[2] * tip1;
    if ((p - closest).norm() <= reach) grabbed_.push_back(i);
    const Real to_tips = (p - tips_midpoint_).norm();
    if (to_tips < best) {
      best = to_tips;
      nearest = i;
    }
  }
  if (grabbed_.empty() && nearest >= 0 && best <= settings_.reach) grabbed_.push_back(nearest);
  std::sort(grabbed_.begin(), grabbed_.end());
  grabbed_.erase(std::unique(grabbed_.begin(), grabbed_.end()), grabbed_.end());

  // x is the state at the start of the coming step, i.e. at the previous pose: offsets are taken
  // in that frame, so that the held vertices move with the tool from where they are (no jump).
  offsets_.clear();
  rest_points_.clear();
  for (const int i : grabbed_) {
    offsets_.push_back(previous_rotation_.transpose() * (row3(x, i) - previous_origin_));
    rest_points_.push_back(row3(rest, i));
  }
  pull_.setZero();
  phase_ = grabbed_.empty() ? GraspPhase::closed_empty : GraspPhase::holding;
  return static_cast<int>(grabbed_.size());
}

std::optional<ReleaseEvent> Grasper::measure(const Points& internal_forces) {
  if (phase_ != GraspPhase::holding) return std::nullopt;
  require(internal_forces.rows() > grabbed_.back(), [&] {
    return "Grasper::measure: internal_forces has " + std::to_string(internal_forces.rows()) +
           " rows, the grasper holds vertex " + std::to_string(grabbed_.back());
  });
  Vec3 sum = Vec3::Zero();
  for (const int i : grabbed_)
    sum += row3(internal_forces, i);
  pull_ = -sum;
  // Not (|pull| <= tear): a NaN force tears too rather than holding forever.
  if (!(pull_.norm() <= settings_.tear_force)) return release(ReleaseReason::torn);
  return std::nullopt;
}

Vec3 Grasper::held_position(std::size_t k) const {
  return origin_ + rotation_ * offsets_[k];
}

void Grasper::prescribe(Prescribed& prescribed) const {
  if (phase_ != GraspPhase::holding) return;
  const int last = grabbed_.back();
  require(prescribed.mask.rows() > last && prescribed.position.rows() > last, [&] {
    return "Grasper::prescribe: mask and position need a row for vertex " + std::to_string(last) +
           ", got " + std::to_string(prescribed.mask.rows()) + " and " +
           std::to_string(prescribed.position.rows()) + " rows";
  });
  for (std::size_t k = 0; k < grabbed_.size(); ++k) {
    const int i = grabbed_[k];
    prescribed.mask.row(i).setOnes();
    prescribed.position.row(i) = held_position(k).transpose();
  }
}

void Grasper::hold(Real dt, Points& x, Points& v) const {
  require(dt > 0 && std::isfinite(dt),
          [&] { return "Grasper::hold: dt must be finite and > 0, got " + number(dt); });
  if (phase_ != GraspPhase::holding) return;
  const int last = grabbed_.back();
  require(x.rows() > last && v.rows() > last, [&] {
    return "Grasper::hold: x and v need a row for vertex " + std::to_string(last) + ", got " +
           std::to_string(x.rows()) + " and " + std::to_string(v.rows()) + " rows";
  });
  for (std::size_t k = 0; k < grabbed_.size(); ++k) {
    const int i = grabbed_[k];
    const Vec3 now = held_position(k);
    const Vec3 before = previous_origin_ + previous_rotation_ * offsets_[k];
    x.row(i) = now.transpose();
    v.row(i) = ((now - before) / dt).transpose();
  }
}

std::optional<ReleaseEvent> Grasper::on_vertex_removed(int vertex) {
  if (phase_ != GraspPhase::holding) return std::nullopt;
  const auto it = std::lower_bound(grabbed_.begin(), grabbed_.end(), vertex);
  if (it == grabbed_.end() || *it != vertex) return std::nullopt;
  const auto k = it - grabbed_.begin();
  grabbed_.erase(it);
  offsets_.erase(offsets_.begin() + k);
  if (grabbed_.empty()) return release(ReleaseReason::lost);
  return std::nullopt;
}

std::optional<ReleaseEvent> Grasper::remap(std::span<const int> old_to_new) {
  if (phase_ != GraspPhase::holding) return std::nullopt;
  const auto n = static_cast<int>(old_to_new.size());
  for (const int i : grabbed_) {
    require(i < n, "Grasper::remap: held vertex " + std::to_string(i) + " is outside old_to_new (" +
                       std::to_string(n) + " entries)");
  }
  // Keep the survivors with their new numbers, then restore the ascending order.
  std::vector<std::size_t> order;
  std::vector<int> renumbered;
  for (std::size_t k = 0; k < grabbed_.size(); ++k) {
    const int j = old_to_new[static_cast<std::size_t>(grabbed_[k])];
    if (j < 0) continue;
    order.push_back(k);
    renumbered.push_back(j);
  }
  std::vector<std::size_t> by_new(order.size());
  for (std::size_t k = 0; k < by_new.size(); ++k)
    by_new[k] = k;
  std::sort(by_new.begin(), by_new.end(),
            [&](std::size_t a, std::size_t b) { return renumbered[a] < renumbered[b]; });
  for (std::size_t k = 1; k < by_new.size(); ++k) {
    require(
        renumbered[by_new[k]] != renumbered[by_new[k - 1]],
        "Grasper::remap: two held vertices map to vertex " + std::to_string(renumbered[by_new[k]]));
  }
  std::vector<int> grabbed;
  std::vector<Vec3> offsets;
  for (const std::size_t k : by_new) {
    grabbed.push_back(renumbered[k]);
    offsets.push_back(offsets_[order[k]]);
  }
  grabbed_ = std::move(grabbed);
  offsets_ = std::move(offsets);
  if (grabbed_.empty()) return release(ReleaseReason::lost);
  return std::nullopt;
}

void Grasper::set_tear_force(Real tear_force) {
  require(tear_force > 0,
          "Grasper::set_tear_force: tear_force must be > 0, got " + number(tear_force));
  settings_.tear_force = tear_force;
}

ReleaseEvent Grasper::release(ReleaseReason reason) {
  ReleaseEvent event;
  event.reason = reason;
  event.pull = pull_;
  event.released_vertices = static_cast<int>(grabbed_.size());
  // The held vertices' rest points (all of them, also those removed since: the region must still
  // cover where refinement added vertices for the grab) widened by the grab reach.
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : rest_points_)
    centre += p;
  if (!rest_points_.empty()) centre /= static_cast<Real>(rest_points_.size());
  Real radius = 0;
  for (const Vec3& p : rest_points_)
    radius = std::max(radius, (p - centre).norm());
  event.resimplify = RestRegion{
      centre, radius + 0.5 * settings_.jaw_length + settings_.jaw_radius + settings_.grab_margin};
  grabbed_.clear();
  offsets_.clear();
  rest_points_.clear();
  pull_.setZero();
  // A torn or lost grasp leaves the jaws closed on nothing: they must open before grabbing again.
  phase_ = reason == ReleaseReason::opened ? GraspPhase::open : GraspPhase::closed_empty;
  return event;
}

}  // namespace incise::sim::tools
