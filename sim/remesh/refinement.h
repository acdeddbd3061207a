#pragma once

// Size and quality control (Paloc 2006, "Quality and size control of the generated elements"):
// Delaunay refinement of the tets of a region in the rest configuration, with the paper's floor on
// the local feature size so that refinement never creates an edge shorter than
// l_min, and so never lowers the stable time step below dt_min (see time_step_floor.h).

#include <limits>
#include <optional>

#include "sim/core/types.h"
#include "sim/remesh/remesh_mesh.h"
#include "sim/remesh/size_field.h"
#include "sim/remesh/state_transfer.h"

namespace incise::sim::remesh {

struct RefinementSettings {
  // The floor [m], > 0: a point closer than l_min to an existing vertex is not inserted. Every
  // edge an insertion creates joins the new vertex to an existing one, so it is >= l_min long.
  Real l_min = 0;
  // The quality bound B (> sqrt(6)/4, the regular tet's ratio): a tet of the region whose
  // circumradius / shortest edge exceeds B is split at its circumcentre. Shewchuk's termination
  // proof needs B > 2; here the floor alone bounds the number of insertions (no two vertices
  // closer than l_min), so any B is safe, but below about 1 the bound is rarely reachable.
  Real max_radius_edge_ratio = 2.0;
  // Also roll back an insertion that creates a tet with an altitude below l_min. The stable
  // step estimate (sim/solve/stable_time_step.h) uses the smallest altitude, which a sliver (a
  // flat tet whose edges are all long) can make far shorter than the shortest edge; with this on,
  // the tets refinement creates keep that estimate >= dt_min too, at the price of leaving more
  // tets unrefined.
  bool floor_altitudes = false;
  // Work bound per call: at most this many insertions; the next call carries on.
  int max_insertions = std::numeric_limits<int>::max();
  // Optional: a ball holding every point where the size field is finite (region_hint_of). With
  // it, a call looks only at the tets near the region instead of scanning every tet (twice: to
  // queue the bad tets and to count the unresolved ones): it walks to the ball's centre (locate)
  // and searches outwards over the tet adjacency, keeping the tets whose bounding sphere (about
  // the centroid) meets the ball. Every tet of the region has its centroid in the ball, so the
  // result is the full scan's, provided the body's part inside the ball is connected (always for
  // a convex body; a ball reaching across a gap of a non-convex organ refines only the part the
  // walk lands in).
  std::optional<RegionHint> region;
};

struct RefinementStats {
  // Insertions kept, by where the point fell: circumcentres strictly inside a tet, on a face or
  // on an edge; splits of a constrained face or edge whose circumcentre or midpoint was taken
  // because the tet's circumcentre lay beyond it (outside the body or across a label interface).
  int in_tet = 0;
  int on_face = 0;
  int on_edge = 0;
  int constraint_splits = 0;
  // Insertions at a point pulled back from the circumcentre towards the centroid, because the
  // circumcentre (or the constraint split it asked for) was refused.
  int pulled_back = 0;
  // Tets given up because every candidate point was refused: at least one for being closer than
  // l_min to an existing vertex; or all as not insertable (beyond a constraint when pulled back,
  // the walk failed, on a vertex, on the free edge of a frozen face, or off a slanted or curved
  // constraint by rounding; see docs/remeshing.md).
  int rejected_l_min = 0;
  int rejected_other = 0;
  // Inserted, then removed again because the floor check after the insertion failed (an edge
  // below l_min the check before it missed, or a tet below the altitude floor).
  int rolled_back = 0;
  // Rolled-back vertices that could not be removed (kCannotRemoveNow): the floor does not hold
  // at them. Not seen in the tests.
  int floor_violations = 0;
  bool budget_exhausted = false;
  // After the call: tets of the region still larger than the target or worse than B, because
  // every point that would split them was refused (or the budget ran out).
  int unresolved_size = 0;
  int unresolved_quality = 0;

  int insertions() const { return in_tet + on_face + on_edge + constraint_splits + pulled_back; }
};

// Refines the region of `target_size` (tets whose centroid it maps to a finite size), worst tet
// first (largest max(circumradius / target, ratio / B)): a tet whose circumradius exceeds the
// target or whose radius-edge ratio exceeds B is split at its circumcentre, located by walking
// from it (locate). If the circumcentre lies beyond a constrained or boundary face, that face is
// split instead (a simplified Shewchuk-style encroachment rule), at its circumcentre if that is
// strictly inside the triangle, else at the midpoint of its longest edge, and the tet is looked
// at again. If that point is refused, points pulled back from the circumcentre towards the
// centroid are tried (see RefinementStats::pulled_back).
// The floor: before an insertion, the point's distance to its nearest vertex (searched in the
// tets within l_min of it) must be >= l_min; after it, the new vertex's edges (and with
// floor_altitudes the new tets' altitudes) are checked again and the insertion is undone by
// remove_vertex if they fail. So no two vertices, one of them inserted, are closer than l_min,
// and the shortest edge of the mesh is >= min(l_min, shortest distance between original vertices).
// The mesh must be constrained Delaunay (make_constrained_delaunay). Every edit is reported to
// `listener`. Throws std::invalid_argument for l_min <= 0, B <= sqrt(6)/4, an empty field, or a
// region hint with a non-finite centre, or a radius that is negative or not finite.
RefinementStats refine(RemeshMesh& mesh, const SizeField& target_size,
                       const RefinementSettings& settings, const RemeshListener& listener = {});

}  // namespace incise::sim::remesh
