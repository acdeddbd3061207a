#pragma once
// Internal to refine() (sim/remesh/refinement*.cpp): the work of one refinement call. Its parts
// are in their own files: the driver in refinement.cpp, the walk over the region in
// refinement_region_walk.cpp, the split points in refinement_split_points.cpp and the l_min floor
// in refinement_floor.cpp.

#include <algorithm>
#include <array>
#include <queue>
#include <set>
#include <vector>

#include "sim/core/types.h"
#include "sim/remesh/point_location.h"
#include "sim/remesh/refinement.h"
#include "sim/remesh/remesh_mesh.h"
#include "sim/remesh/size_field.h"
#include "sim/remesh/state_transfer.h"

namespace incise::sim::remesh {

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

inline std::array<Vec3, 4> corners(const RemeshMesh& mesh, int t) {
  const TetVertices& v = mesh.tet(t);
  return {mesh.point(v[0]), mesh.point(v[1]), mesh.point(v[2]), mesh.point(v[3])};
}

inline TetVertices sorted(TetVertices v) {
  std::sort(v.begin(), v.end());
  return v;
}

// The work of one refinement call, with scratch reused across insertions.
class Refiner {
 public:
  Refiner(RemeshMesh& mesh, const SizeField& target_size, const RefinementSettings& settings,
          const RemeshListener& listener)
      : mesh_(mesh), target_size_(target_size), settings_(settings), listener_(listener) {}

  RefinementStats run();

 private:
  void consider(int t);
  // A fresh mark for visited_, sized to the tet slots.
  void next_stamp();
  enum class Outcome { kInserted, kTooClose, kNotInsertable, kRolledBack };

  // In refinement_region_walk.cpp: the region's tets.

  // The tets that may be in the region, into region_tets_: every alive tet without a hint; with
  // RefinementSettings::region, the tets whose bounding sphere meets the ball, found by a
  // breadth-first search from a tet that meets it (see the setting for when that holds).
  void gather_region_tets();
  // True if tet t's bounding sphere about its centroid meets the hint's ball.
  bool meets(int t, const RegionHint& hint) const;
  // A tet that really meets the hint's ball (point_tet_distance of the centre <= radius), so that
  // it lies in the connected part of the region the search must cover; -1 if none was found.
  // The walk to the centre stops at a constrained face: across an interior one (a label
  // interface) it carries on from the other side; at the surface (centre outside the body) it
  // descends to the neighbour nearest the centre while that gets nearer.
  int seed_tet(const RegionHint& hint);
  Real center_distance(int t, const RegionHint& hint) const;

  // In refinement_split_points.cpp: where a tet is split.

  // Tries to split tet t at its circumcentre, or where the circumcentre says (the constrained
  // face it lies beyond); if that point is refused, at points pulled back towards the centroid,
  // centroid + 2^-k (circumcentre - centroid) for k = 1 .. kPullBacks, each inside t's
  // circumsphere and so still destroying t (Delaunay). A tet all of whose points are refused is
  // not tried again in this call.
  void split(int t);
  // Split point number i (0 .. kConstraintCandidates - 1) of the constrained face `where`
  // (tet, face): 0 its circumcentre if strictly inside it, 1 .. 3 the midpoints of its edges,
  // longest first, 4 its centroid; `where` becomes the face or edge to insert on (or stays
  // kBeyondConstraint for a circumcentre outside the face). As point_on_face / point_on_edge,
  // exact on an axis-aligned face (the shared coordinate is copied); on a slanted one rounding
  // usually puts them off the plane and insertion refuses them (kOffConstraint).
  Vec3 constraint_split_point(int i, Location* where);

  // In refinement_floor.cpp: the l_min floor.

  // Inserts p at `where` unless it is refused; `before` is the tet being split.
  Outcome try_insert(const Location& where, const Vec3& p, const TetVertices& before);
  // The distance from p to its nearest vertex, exact when that is below l_min (else some value
  // >= l_min): the vertices of every tet whose bounding box comes within l_min of p, reached
  // from `start` (whose closure holds p) across faces, constrained or not. These include every
  // tet meeting the ball B(p, l_min), which are face-connected when the ball's part of the body
  // is (always for a convex body; a ball reaching across a thin gap of a non-convex organ
  // could miss a vertex beyond it). The cavity of an insertion may be larger, but its other
  // vertices are farther than l_min anyway.
  Real nearest_vertex_distance(int start, const Vec3& p);
  // Predicts whether the tets an insertion of p at `where` creates are all at least l_min high:
  // they are p joined to the faces of its Delaunay cavity (the tets whose circumsphere holds p,
  // grown from the tets around `where` across unconstrained faces), except faces p lies on
  // (split, not coned). A prediction only: floor_holds checks what the insertion's flips made.
  // It spares the insertion and its roll-back for points the floor would refuse anyway, and
  // keeps roll-backs rare, which matters because a roll-back next to a frozen face can fail
  // (RefinementStats::floor_violations).
  bool cavity_meets_floor(const Location& where, const Vec3& p);
  // The floor at the new vertex v: every edge from it >= l_min and, with floor_altitudes, every
  // tet created at least l_min high.
  bool floor_holds(int v, const TetChanges& changes);

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

}  // namespace incise::sim::remesh
