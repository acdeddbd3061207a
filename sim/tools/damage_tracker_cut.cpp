// DamageTracker::record_cut (damage_tracker.h): the crack faces of one cut event against the
// marked target and the protected labels.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/tools/damage_tracker.h"

namespace incise::sim::tools {
namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument("DamageTracker::record_cut: " + what);
}

}  // namespace

CutDamage DamageTracker::record_cut(const Points& rest, const Triangles& crack_faces) {
  const auto nodes = static_cast<std::size_t>(rest.rows());
  for (int f = 0; f < crack_faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (crack_faces(f, k) < 0 || crack_faces(f, k) >= rest.rows())
        fail("crack face " + std::to_string(f) + " holds node " +
             std::to_string(crack_faces(f, k)) + ", outside [0, " + std::to_string(rest.rows()) +
             ")");
    }
  }
  // Node -> alive tets (compressed rows), to find the one tet that holds each crack face.
  std::vector<int> start(nodes + 1, 0);
  for (int s = 0; s < num_slots(); ++s) {
    if (!alive_[static_cast<std::size_t>(s)]) continue;
    for (int k = 0; k < 4; ++k) {
      const int node = tets_(s, k);
      if (node < 0 || static_cast<std::size_t>(node) >= nodes)
        fail("rest has " + std::to_string(rest.rows()) + " rows, tet slot " + std::to_string(s) +
             " uses node " + std::to_string(node));
      ++start[static_cast<std::size_t>(node) + 1];
    }
  }
  for (std::size_t i = 0; i < nodes; ++i)
    start[i + 1] += start[i];
  std::vector<int> tets_of(static_cast<std::size_t>(start[nodes]));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int s = 0; s < num_slots(); ++s) {
    if (!alive_[static_cast<std::size_t>(s)]) continue;
    for (int k = 0; k < 4; ++k)
      tets_of[static_cast<std::size_t>(fill[static_cast<std::size_t>(tets_(s, k))]++)] = s;
  }
  auto holds = [&](int s, int node) { return (tets_.row(s).array() == node).any(); };

  std::vector<int> labels(static_cast<std::size_t>(crack_faces.rows()));
  for (int f = 0; f < crack_faces.rows(); ++f) {
    const int a = crack_faces(f, 0), b = crack_faces(f, 1), c = crack_faces(f, 2);
    int owner = -1;
    for (int j = start[static_cast<std::size_t>(a)]; j < start[static_cast<std::size_t>(a) + 1];
         ++j) {
      const int s = tets_of[static_cast<std::size_t>(j)];
      if (holds(s, b) && holds(s, c)) owner = s;
    }
    if (owner < 0)
      fail("no alive tet holds crack face " + std::to_string(f) + " (" + std::to_string(a) + ", " +
           std::to_string(b) + ", " + std::to_string(c) + "): call update_elements first");
    labels[static_cast<std::size_t>(f)] = label_[static_cast<std::size_t>(owner)];
  }
  return record_cut(rest, crack_faces, labels);
}

CutDamage DamageTracker::record_cut(const Points& rest, const Triangles& crack_faces,
                                    std::span<const int> labels) {
  if (labels.size() != static_cast<std::size_t>(crack_faces.rows()))
    fail("labels has " + std::to_string(labels.size()) + " entries for " +
         std::to_string(crack_faces.rows()) + " crack faces");
  for (int f = 0; f < crack_faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (crack_faces(f, k) < 0 || crack_faces(f, k) >= rest.rows())
        fail("crack face " + std::to_string(f) + " holds node " +
             std::to_string(crack_faces(f, k)) + ", outside [0, " + std::to_string(rest.rows()) +
             ")");
    }
  }
  const MarkedTarget& target = settings_.target;
  CutDamage cut;
  Real weighted = 0;
  for (int f = 0; f < crack_faces.rows(); ++f) {
    const int a = crack_faces(f, 0), b = crack_faces(f, 1), c = crack_faces(f, 2);
    const Vec3 pa = row3(rest, a), pb = row3(rest, b), pc = row3(rest, c);
    // Each rest triangle of the cut surface appears twice, once per side of the crack.
    const Real area = (pb - pa).cross(pc - pa).norm() / 4;
    cut.area += area;
    const int label = labels[static_cast<std::size_t>(f)];
    if (std::find(settings_.protected_labels.begin(), settings_.protected_labels.end(), label) !=
        settings_.protected_labels.end())
      cut.protected_area += area;
    if (target.empty()) {
      cut.area_outside_target += area;
      continue;
    }
    const Real d = distance_to_target(target, (pa + pb + pc) / 3);
    (d <= target.half_width ? cut.area_inside_target : cut.area_outside_target) += area;
    weighted += area * d;
    cut.max_distance = std::max(cut.max_distance, d);
  }
  cut.mean_distance = cut.area > 0 ? weighted / cut.area : Real(0);
  cut.never_event = cut.protected_area > 0;

  if (crack_faces.rows() > 0) ++totals_.cut_events;
  totals_.cut_area += cut.area;
  totals_.cut_area_outside_target += cut.area_outside_target;
  totals_.cut_max_distance = std::max(totals_.cut_max_distance, cut.max_distance);
  totals_.protected_cut_area += cut.protected_area;
  totals_.never_event = totals_.never_event || cut.never_event;
  weighted_distance_ += weighted;
  return cut;
}

}  // namespace incise::sim::tools
