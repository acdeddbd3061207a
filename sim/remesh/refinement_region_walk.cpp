// The refinement's region walk: the tets that may be in the region, found by a breadth-first
// search from a tet that meets the region's ball (RefinementSettings::region).
#include <algorithm>
#include <cmath>

#include "sim/remesh/adaptation_regions.h"
#include "sim/remesh/point_location.h"
#include "sim/remesh/refiner.h"

namespace incise::sim::remesh {

void Refiner::gather_region_tets() {
  region_tets_.clear();
  if (!settings_.region) {
    for (int t = 0; t < mesh_.num_tet_slots(); ++t) {
      if (mesh_.tet_alive(t)) region_tets_.push_back(t);
    }
    return;
  }
  const RegionHint& hint = *settings_.region;
  const int seed = seed_tet(hint);
  if (seed < 0) {
    for (int t = 0; t < mesh_.num_tet_slots(); ++t) {
      if (mesh_.tet_alive(t) && meets(t, hint)) region_tets_.push_back(t);
    }
    return;
  }
  next_stamp();
  region_tets_.push_back(seed);
  visited_[static_cast<size_t>(seed)] = stamp_;
  for (size_t i = 0; i < region_tets_.size(); ++i) {
    const int t = region_tets_[i];
    for (int k = 0; k < 4; ++k) {
      const int n = mesh_.neighbor(t, k);
      if (n < 0 || visited_[static_cast<size_t>(n)] == stamp_) continue;
      visited_[static_cast<size_t>(n)] = stamp_;
      if (meets(n, hint)) region_tets_.push_back(n);
    }
  }
}

bool Refiner::meets(int t, const RegionHint& hint) const {
  const auto x = corners(mesh_, t);
  const Vec3 centroid = (x[0] + x[1] + x[2] + x[3]) / 4;
  Real radius2 = 0;
  for (const Vec3& corner : x)
    radius2 = std::max(radius2, (corner - centroid).squaredNorm());
  return intersects(hint, centroid, std::sqrt(radius2));
}

int Refiner::seed_tet(const RegionHint& hint) {
  constexpr int kMaxHops = 64;      // label interfaces crossed on the way
  constexpr int kMaxDescent = 256;  // steps along the surface towards the centre
  int start = 0;
  while (start < mesh_.num_tet_slots() && !mesh_.tet_alive(start))
    ++start;
  if (start == mesh_.num_tet_slots()) return -1;
  Location where = locate(mesh_, start, hint.center);
  for (int hop = 0; hop < kMaxHops && where.kind == LocationKind::kBeyondConstraint; ++hop) {
    const int across = mesh_.neighbor(where.tet, where.face);
    if (across < 0) break;
    where = locate(mesh_, across, hint.center);
  }
  if (where.tet < 0) return -1;
  int t = where.tet;
  Real distance = center_distance(t, hint);
  for (int step = 0; step < kMaxDescent && distance > hint.radius; ++step) {
    int nearest = -1;
    for (int k = 0; k < 4; ++k) {
      const int n = mesh_.neighbor(t, k);
      if (n < 0) continue;
      const Real d = center_distance(n, hint);
      if (d < distance) {
        distance = d;
        nearest = n;
      }
    }
    if (nearest < 0) break;
    t = nearest;
  }
  return distance <= hint.radius ? t : -1;
}

Real Refiner::center_distance(int t, const RegionHint& hint) const {
  const auto x = corners(mesh_, t);
  return point_tet_distance(hint.center, x[0], x[1], x[2], x[3]);
}

}  // namespace incise::sim::remesh
