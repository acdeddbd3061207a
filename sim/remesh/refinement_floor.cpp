// The refinement's l_min floor: the checks before an insertion (the nearest vertex, the predicted
// cavity) and after it (the new vertex's edges and tets), and the roll-back when they fail.
#include <algorithm>
#include <limits>

#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/predicates.h"
#include "sim/remesh/refiner.h"
#include "sim/remesh/tet_shape.h"
#include "sim/remesh/vertex_removal.h"

namespace incise::sim::remesh {
namespace {

bool same_tet(const TetVertices& a, const TetVertices& b) {
  return sorted(a) == sorted(b);
}

}  // namespace

Refiner::Outcome Refiner::try_insert(const Location& where, const Vec3& p,
                                     const TetVertices& before) {
  if (where.kind != LocationKind::kInTet && where.kind != LocationKind::kOnFace &&
      where.kind != LocationKind::kOnEdge) {
    return Outcome::kNotInsertable;
  }
  if (nearest_vertex_distance(where.tet, p) < settings_.l_min) return Outcome::kTooClose;
  if (settings_.floor_altitudes && !cavity_meets_floor(where, p)) return Outcome::kTooClose;
  const LocatedInsertion ins = insert_located(mesh_, where, p);
  if (ins.result.status != InsertStatus::kInserted) return Outcome::kNotInsertable;
  if (listener_.on_inserted) listener_.on_inserted(ins.inserted, ins.result.changes);
  if (floor_holds(ins.result.vertex, ins.result.changes)) {
    for (int c : ins.result.changes.created) {
      if (mesh_.tet_alive(c)) consider(c);
    }
    return Outcome::kInserted;
  }
  ++stats_.rolled_back;
  const RemoveResult undo = remove_vertex(mesh_, ins.result.vertex);
  if (listener_.on_removal) listener_.on_removal(ins.result.vertex, undo);
  if (undo.status != RemoveStatus::kRemoved) {
    ++stats_.floor_violations;
    for (int c : ins.result.changes.created) {
      if (mesh_.tet_alive(c)) consider(c);
    }
    return Outcome::kInserted;
  }
  // The undo recreates the tets from before the insertion (the constrained Delaunay mesh is
  // unique) in new slots, so their queue entries are stale: queue them again, except the tet
  // being split, whose slot is remembered for its next candidate point.
  for (int c : undo.changes.created) {
    if (!mesh_.tet_alive(c)) continue;
    if (same_tet(mesh_.tet(c), before)) {
      rolled_back_slot_ = c;
    } else {
      consider(c);
    }
  }
  return Outcome::kRolledBack;
}

Real Refiner::nearest_vertex_distance(int start, const Vec3& p) {
  next_stamp();
  Real nearest = std::numeric_limits<Real>::infinity();
  near_.assign(1, start);
  visited_[static_cast<size_t>(start)] = stamp_;
  for (size_t i = 0; i < near_.size(); ++i) {
    const int t = near_[i];
    for (int k = 0; k < 4; ++k) {
      nearest = std::min(nearest, (mesh_.point(mesh_.tet(t)[k]) - p).norm());
      const int n = mesh_.neighbor(t, k);
      if (n < 0 || visited_[static_cast<size_t>(n)] == stamp_) continue;
      visited_[static_cast<size_t>(n)] = stamp_;
      const auto x = corners(mesh_, n);
      const Vec3 lo = x[0].cwiseMin(x[1]).cwiseMin(x[2]).cwiseMin(x[3]);
      const Vec3 hi = x[0].cwiseMax(x[1]).cwiseMax(x[2]).cwiseMax(x[3]);
      const Vec3 gap = (lo - p).cwiseMax(p - hi).cwiseMax(Vec3::Zero());
      if (gap.norm() <= settings_.l_min) near_.push_back(n);
    }
  }
  return nearest;
}

bool Refiner::cavity_meets_floor(const Location& where, const Vec3& p) {
  cavity_.clear();
  if (where.kind == LocationKind::kOnEdge) {
    const int start = mesh_.find_edge_tet(where.a, where.b);
    if (start < 0) return true;
    mesh_.edge_ring(where.a, where.b, start, &cavity_);
  } else {
    cavity_.push_back(where.tet);
    const int across =
        where.kind == LocationKind::kOnFace ? mesh_.neighbor(where.tet, where.face) : -1;
    if (across >= 0) cavity_.push_back(across);
  }
  if (static_cast<int>(in_cavity_.size()) < mesh_.num_tet_slots()) {
    in_cavity_.resize(static_cast<size_t>(mesh_.num_tet_slots()), 0);
  }
  ++cavity_stamp_;
  for (int t : cavity_)
    in_cavity_[static_cast<size_t>(t)] = cavity_stamp_;
  next_stamp();  // visited_: tets whose circumsphere was tested
  for (size_t i = 0; i < cavity_.size(); ++i) {
    const int t = cavity_[i];
    for (int k = 0; k < 4; ++k) {
      const int n = mesh_.neighbor(t, k);
      if (n < 0 || mesh_.face_parent(t, k) >= 0) continue;
      const size_t ns = static_cast<size_t>(n);
      if (in_cavity_[ns] == cavity_stamp_ || visited_[ns] == stamp_) continue;
      visited_[ns] = stamp_;
      const auto x = corners(mesh_, n);
      if (side_of_sphere(x[0], x[1], x[2], x[3], p) > 0) {
        in_cavity_[ns] = cavity_stamp_;
        cavity_.push_back(n);
      }
    }
  }
  for (const int t : cavity_) {
    for (int k = 0; k < 4; ++k) {
      const int n = mesh_.neighbor(t, k);
      if (n >= 0 && in_cavity_[static_cast<size_t>(n)] == cavity_stamp_) continue;
      const TetVertices& v = mesh_.tet(t);
      const Vec3& a = mesh_.point(v[kTetFaces[k][0]]);
      const Vec3& b = mesh_.point(v[kTetFaces[k][1]]);
      const Vec3& c = mesh_.point(v[kTetFaces[k][2]]);
      if (orientation(a, b, c, p) == 0) continue;  // p is on this face: it is split
      // The face's normal points out of t, away from p: (a, c, b, p) is positive.
      if (tet_shape(a, c, b, p).min_altitude < settings_.l_min) return false;
    }
  }
  return true;
}

bool Refiner::floor_holds(int v, const TetChanges& changes) {
  mesh_.star(v, &star_);
  for (int t : star_) {
    for (int k = 0; k < 4; ++k) {
      const int u = mesh_.tet(t)[k];
      if (u != v && (mesh_.point(u) - mesh_.point(v)).norm() < settings_.l_min) return false;
    }
  }
  if (!settings_.floor_altitudes) return true;
  for (int t : changes.created) {
    if (!mesh_.tet_alive(t)) continue;
    const auto x = corners(mesh_, t);
    if (tet_shape(x[0], x[1], x[2], x[3]).min_altitude < settings_.l_min) return false;
  }
  return true;
}

}  // namespace incise::sim::remesh
