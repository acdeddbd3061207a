#include "sim/remesh/refinement.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/adaptation_regions.h"
#include "sim/remesh/point_location.h"
#include "sim/remesh/predicates.h"
#include "sim/remesh/tet_shape.h"
#include "sim/remesh/vertex_removal.h"

namespace incise::sim::remesh {
namespace {

struct Candidate {
  Real badness;  // max(circumradius / target, ratio / B) > 1
  int tet;
  TetVertices vertices;  // to recognise a slot that has been reused since
  // Worst first; ties (common on regular meshes) by slot and then vertices, a total order, so the
  // tets are split in the same order whatever order they were queued in (the full scan and the
  // region walk of RefinementSettings::region queue them differently).
  bool operator<(const Candidate& other) const {
    if (badness != other.badness) return badness < other.badness;
    if (tet != other.tet) return tet > other.tet;
    return vertices > other.vertices;
  }
};

struct Badness {
  bool too_large = false;
  bool too_poor = false;
  Real value = 0;
};

std::array<Vec3, 4> corners(const RemeshMesh& mesh, int t) {
  const TetVertices& v = mesh.tet(t);
  return {mesh.point(v[0]), mesh.point(v[1]), mesh.point(v[2]), mesh.point(v[3])};
}

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

TetVertices sorted(TetVertices v) {
  std::sort(v.begin(), v.end());
  return v;
}

bool same_tet(const TetVertices& a, const TetVertices& b) {
  return sorted(a) == sorted(b);
}

// Split points tried on a constrained face (see Refiner::constraint_split_point).
constexpr int kConstraintCandidates = 5;

// The work of one refinement call, with scratch reused across insertions.
class Refiner {
 public:
  Refiner(RemeshMesh& mesh, const SizeField& target_size, const RefinementSettings& settings,
          const RemeshListener& listener)
      : mesh_(mesh), target_size_(target_size), settings_(settings), listener_(listener) {}

  RefinementStats run() {
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

 private:
  void consider(int t) {
    if (!given_up_.empty() && given_up_.count(sorted(mesh_.tet(t)))) return;
    const Badness bad = badness(mesh_, t, target_size_, settings_.max_radius_edge_ratio);
    if (bad.too_large || bad.too_poor) queue_.push({bad.value, t, mesh_.tet(t)});
  }

  // The tets that may be in the region, into region_tets_: every alive tet without a hint; with
  // RefinementSettings::region, the tets whose bounding sphere meets the ball, found by a
  // breadth-first search from a tet that meets it (see the setting for when that holds).
  void gather_region_tets() {
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

  // True if tet t's bounding sphere about its centroid meets the hint's ball.
  bool meets(int t, const RegionHint& hint) const {
    const auto x = corners(mesh_, t);
    const Vec3 centroid = (x[0] + x[1] + x[2] + x[3]) / 4;
    Real radius2 = 0;
    for (const Vec3& corner : x)
      radius2 = std::max(radius2, (corner - centroid).squaredNorm());
    return intersects(hint, centroid, std::sqrt(radius2));
  }

  // A tet that really meets the hint's ball (point_tet_distance of the centre <= radius), so that
  // it lies in the connected part of the region the search must cover; -1 if none was found.
  // The walk to the centre stops at a constrained face: across an interior one (a label
  // interface) it carries on from the other side; at the surface (centre outside the body) it
  // descends to the neighbour nearest the centre while that gets nearer.
  int seed_tet(const RegionHint& hint) {
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

  Real center_distance(int t, const RegionHint& hint) const {
    const auto x = corners(mesh_, t);
    return point_tet_distance(hint.center, x[0], x[1], x[2], x[3]);
  }

  // A fresh mark for visited_, sized to the tet slots.
  void next_stamp() {
    if (static_cast<int>(visited_.size()) < mesh_.num_tet_slots()) {
      visited_.resize(static_cast<size_t>(mesh_.num_tet_slots()), 0);
    }
    ++stamp_;
  }

  enum class Outcome { kInserted, kTooClose, kNotInsertable, kRolledBack };

  // Tries to split tet t at its circumcentre, or where the circumcentre says (the constrained
  // face it lies beyond); if that point is refused, at points pulled back towards the centroid,
  // centroid + 2^-k (circumcentre - centroid) for k = 1 .. kPullBacks, each inside t's
  // circumsphere and so still destroying t (Delaunay). A tet all of whose points are refused is
  // not tried again in this call.
  void split(int t) {
    constexpr int kPullBacks = 3;
    const TetVertices before = mesh_.tet(t);
    const auto x = corners(mesh_, t);
    const Vec3 center = circumcenter(x[0], x[1], x[2], x[3]);
    const Vec3 centroid = (x[0] + x[1] + x[2] + x[3]) / 4;
    bool too_close = false;
    int constraint_candidate = 0;
    for (int k = 0; k <= kPullBacks; ++k) {
      Vec3 p = k == 0 ? center : Vec3(centroid + std::ldexp(1.0, -k) * (center - centroid));
      Location where = locate(mesh_, t, p);
      const bool constraint_split = where.kind == LocationKind::kBeyondConstraint && k == 0;
      if (constraint_split) {
        p = constraint_split_point(constraint_candidate++, &where);
        // Stay at k = 0 for the face's other split points while this one is refused (an input
        // vertex near the surface), walking again since a refused insertion may have moved t.
        if (constraint_candidate < kConstraintCandidates) --k;
        if (where.kind == LocationKind::kBeyondConstraint) continue;
      }
      const Outcome outcome = try_insert(where, p, before);
      if (outcome == Outcome::kInserted) {
        if (constraint_split) {
          ++stats_.constraint_splits;
        } else if (k > 0) {
          ++stats_.pulled_back;
        } else if (where.kind == LocationKind::kInTet) {
          ++stats_.in_tet;
        } else if (where.kind == LocationKind::kOnFace) {
          ++stats_.on_face;
        } else {
          ++stats_.on_edge;
        }
        // A split of a constrained face elsewhere may leave t as it was: look at it again.
        if (mesh_.tet_alive(t) && mesh_.tet(t) == before) consider(t);
        return;
      }
      too_close = too_close || outcome == Outcome::kTooClose || outcome == Outcome::kRolledBack;
      if (outcome == Outcome::kRolledBack) t = rolled_back_slot_;  // t was recreated elsewhere
    }
    ++(too_close ? stats_.rejected_l_min : stats_.rejected_other);
    given_up_.insert(sorted(before));
  }

  // Inserts p at `where` unless it is refused; `before` is the tet being split.
  Outcome try_insert(const Location& where, const Vec3& p, const TetVertices& before) {
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

  // Split point number i (0 .. kConstraintCandidates - 1) of the constrained face `where`
  // (tet, face): 0 its circumcentre if strictly inside it, 1 .. 3 the midpoints of its edges,
  // longest first, 4 its centroid; `where` becomes the face or edge to insert on (or stays
  // kBeyondConstraint for a circumcentre outside the face). As point_on_face / point_on_edge,
  // exact on an axis-aligned face (the shared coordinate is copied); on a slanted one rounding
  // usually puts them off the plane and insertion refuses them (kOffConstraint).
  Vec3 constraint_split_point(int i, Location* where) {
    const TetVertices& tv = mesh_.tet(where->tet);
    const int a = tv[kTetFaces[where->face][0]], b = tv[kTetFaces[where->face][1]],
              c = tv[kTetFaces[where->face][2]];
    if (i == 0) {
      const Vec3 u = mesh_.point(b) - mesh_.point(a), w = mesh_.point(c) - mesh_.point(a);
      // Circumcentre a + s u + r w: (s u + r w) . u = |u|^2 / 2 and (s u + r w) . w = |w|^2 / 2.
      const Real uu = u.dot(u), uw = u.dot(w), ww = w.dot(w);
      const Real det = uu * ww - uw * uw;
      const Real s = (ww * uu - uw * ww) / (2 * det), r = (uu * ww - uw * uu) / (2 * det);
      if (!(s > 0 && r > 0 && s + r < 1)) return Vec3::Zero();
      where->kind = LocationKind::kOnFace;
      return point_on_face(mesh_, a, b, c, s, r);
    }
    if (i == 4) {
      where->kind = LocationKind::kOnFace;
      return point_on_face(mesh_, a, b, c, Real(1) / 3, Real(1) / 3);
    }
    std::array<std::array<int, 2>, 3> ends = {{{a, b}, {b, c}, {c, a}}};
    const auto length = [&](const std::array<int, 2>& e) {
      return (mesh_.point(e[1]) - mesh_.point(e[0])).squaredNorm();
    };
    std::sort(ends.begin(), ends.end(),
              [&](const auto& e, const auto& f) { return length(e) > length(f); });
    where->kind = LocationKind::kOnEdge;
    where->a = ends[static_cast<size_t>(i - 1)][0];
    where->b = ends[static_cast<size_t>(i - 1)][1];
    return point_on_edge(mesh_, where->a, where->b, 0.5);
  }

  // The distance from p to its nearest vertex, exact when that is below l_min (else some value
  // >= l_min): the vertices of every tet whose bounding box comes within l_min of p, reached
  // from `start` (whose closure holds p) across faces, constrained or not. These include every
  // tet meeting the ball B(p, l_min), which are face-connected when the ball's part of the body
  // is (always for a convex body; a ball reaching across a thin gap of a non-convex organ
  // could miss a vertex beyond it). The cavity of an insertion may be larger, but its other
  // vertices are farther than l_min anyway.
  Real nearest_vertex_distance(int start, const Vec3& p) {
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

  // Predicts whether the tets an insertion of p at `where` creates are all at least l_min high:
  // they are p joined to the faces of its Delaunay cavity (the tets whose circumsphere holds p,
  // grown from the tets around `where` across unconstrained faces), except faces p lies on
  // (split, not coned). A prediction only: floor_holds checks what the insertion's flips made.
  // It spares the insertion and its roll-back for points the floor would refuse anyway, and
  // keeps roll-backs rare, which matters because a roll-back next to a frozen face can fail
  // (RefinementStats::floor_violations).
  bool cavity_meets_floor(const Location& where, const Vec3& p) {
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

  // The floor at the new vertex v: every edge from it >= l_min and, with floor_altitudes, every
  // tet created at least l_min high.
  bool floor_holds(int v, const TetChanges& changes) {
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

  RemeshMesh& mesh_;
  const SizeField& target_size_;
  const RefinementSettings& settings_;
  const RemeshListener& listener_;
  RefinementStats stats_;
  std::priority_queue<Candidate> queue_;
  std::vector<int> visited_;
  int stamp_ = 0;
  std::vector<int> near_;
  std::vector<int> region_tets_;
  // Tets (as sorted vertex sets) whose every point was refused: not tried again in this call,
  // also when an undo recreates them in another slot.
  std::set<TetVertices> given_up_;
  int rolled_back_slot_ = -1;
  std::vector<int> star_;
  // Scratch of cavity_meets_floor.
  std::vector<int> cavity_;
  std::vector<int> in_cavity_;
  int cavity_stamp_ = 0;
};

}  // namespace

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
