// Size and quality control: refine() checks its settings and runs a Refiner, which queues the
// region's tets worst first and splits them until none is too large or too poor (refiner.h).
#include "sim/remesh/refinement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/remesh/refiner.h"
#include "sim/remesh/tet_shape.h"

namespace incise::sim::remesh {
namespace {

struct Badness {
  bool too_large = false;
  bool too_poor = false;
  Real value = 0;
};

Badness badness(const RemeshMesh& mesh, int t, const SizeField& target_size, Real bound) {
  const auto x = corners(mesh, t);
  Badness bad;
  const Real target = target_size((x[0] + x[1] + x[2] + x[3]) / 4);
  if (!std::isfinite(target)) return bad;
  const TetShape shape = tet_shape(x[0], x[1], x[2], x[3]);
  bad.too_large = shape.circumradius > target;
  bad.too_poor = shape.radius_edge_ratio > bound;
  bad.value = std::max(shape.circumradius / target, shape.radius_edge_ratio / bound);
  return bad;
}

}  // namespace

RefinementStats Refiner::run() {
  gather_region_tets();
  for (int t : region_tets_)
    consider(t);
  while (!queue_.empty()) {
    if (stats_.insertions() >= settings_.max_insertions) {
      stats_.budget_exhausted = true;
      break;
    }
    const Candidate c = queue_.top();
    queue_.pop();
    if (!mesh_.tet_alive(c.tet) || mesh_.tet(c.tet) != c.vertices) continue;  // stale
    split(c.tet);
  }
  gather_region_tets();
  for (int t : region_tets_) {
    const Badness bad = badness(mesh_, t, target_size_, settings_.max_radius_edge_ratio);
    stats_.unresolved_size += bad.too_large;
    stats_.unresolved_quality += bad.too_poor;
  }
  return stats_;
}

void Refiner::consider(int t) {
  if (!given_up_.empty() && given_up_.count(sorted(mesh_.tet(t)))) return;
  const Badness bad = badness(mesh_, t, target_size_, settings_.max_radius_edge_ratio);
  if (bad.too_large || bad.too_poor) queue_.push({bad.value, t, mesh_.tet(t)});
}

void Refiner::next_stamp() {
  if (static_cast<int>(visited_.size()) < mesh_.num_tet_slots()) {
    visited_.resize(static_cast<size_t>(mesh_.num_tet_slots()), 0);
  }
  ++stamp_;
}

RefinementStats refine(RemeshMesh& mesh, const SizeField& target_size,
                       const RefinementSettings& settings, const RemeshListener& listener) {
  if (!(settings.l_min > 0)) {
    throw std::invalid_argument("refinement l_min must be > 0, got " +
                                std::to_string(settings.l_min));
  }
  if (!(settings.max_radius_edge_ratio > kRegularRadiusEdgeRatio)) {
    throw std::invalid_argument(
        "refinement radius-edge bound must exceed sqrt(6)/4 (the regular tet's), got " +
        std::to_string(settings.max_radius_edge_ratio));
  }
  if (!target_size) throw std::invalid_argument("refinement needs a size field");
  if (settings.region && !(settings.region->radius >= 0 && settings.region->center.allFinite() &&
                           std::isfinite(settings.region->radius))) {
    throw std::invalid_argument("refinement region hint needs a finite centre and radius >= 0");
  }
  return Refiner(mesh, target_size, settings, listener).run();
}

}  // namespace incise::sim::remesh
