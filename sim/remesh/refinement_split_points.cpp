// The refinement's split points: a tet's circumcentre, the split points of the constrained face
// it lies beyond, and points pulled back towards the centroid when those are refused.
#include <algorithm>
#include <array>
#include <cmath>

#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/insertion.h"
#include "sim/remesh/refiner.h"
#include "sim/remesh/tet_shape.h"

namespace incise::sim::remesh {
namespace {

// Split points tried on a constrained face (see Refiner::constraint_split_point).
constexpr int kConstraintCandidates = 5;

}  // namespace

void Refiner::split(int t) {
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

Vec3 Refiner::constraint_split_point(int i, Location* where) {
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

}  // namespace incise::sim::remesh
