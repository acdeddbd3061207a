#pragma once

#include "sim/remesh/flips.h"
#include "sim/remesh/remesh_mesh.h"

namespace incise::sim::remesh {

enum class InsertStatus {
  kInserted,
  // A tet of the split would not be positively oriented: the point is not strictly inside the
  // tet, face or edge named (or coincides with a vertex).
  kNotInside,
  // The face or edge named lies on a constrained surface and the point is not exactly on it
  // (exact test), so inserting it would move the organ surface or a label interface.
  kOffConstraint,
  // The edge is the free edge of a lone constrained face (a face frozen by
  // make_constrained_delaunay): a vertex there could not be removed again, since the
  // constrained faces through it would not cut its star into sides.
  kOnFreeConstraintEdge,
};

struct InsertResult {
  InsertStatus status = InsertStatus::kNotInside;
  int vertex = -1;     // the new vertex id if inserted
  TetChanges changes;  // tets removed and created, the Delaunay restoration included
  FlipCounts flips;    // the flips of the restoration
  // Every face of every created tet is locally Delaunay afterwards. Guaranteed by the flip
  // algorithm when a constrained Delaunay mesh exists with the new vertex (always for a
  // convex domain whose label interfaces are planes across it, like the boxes of the tests;
  // in 3D not in general, e.g. next to faces frozen by make_constrained_delaunay).
  bool delaunay_restored = false;
};

// Point insertion in the rest configuration (the caller has located the point), followed by
// the flip queue (restore_delaunay) that makes the mesh constrained Delaunay again. On any
// status but kInserted the mesh is unchanged.

// p strictly inside tet t: 1-4 split.
InsertResult insert_in_tet(RemeshMesh& mesh, int t, const Vec3& p);

// p on face k of tet t: 2-6 split of the two tets sharing it, or 1-3 on the boundary. On a
// constrained face p must be exactly coplanar with it; the three sub-faces keep its parent.
// (For an unconstrained face, p may be off the plane as long as all six tets are positive.)
InsertResult insert_on_face(RemeshMesh& mesh, int t, int k, const Vec3& p);

// p on the edge (a, b): every tet around the edge splits in two. If a face around the edge is
// constrained (a boundary or interface edge) p must be exactly on the segment; the split
// sub-faces keep their parents. An edge with exactly one constrained face around it inside the
// mesh is refused (kOnFreeConstraintEdge).
InsertResult insert_on_edge(RemeshMesh& mesh, int a, int b, const Vec3& p);

// Points on a face or an edge for the calls above, computed as a + s (b - a) + t (c - a), so
// that a coordinate shared by the corners (an axis-aligned face) is reproduced exactly.
Vec3 point_on_face(const RemeshMesh& mesh, int a, int b, int c, Real s, Real t);
Vec3 point_on_edge(const RemeshMesh& mesh, int a, int b, Real s);

}  // namespace incise::sim::remesh
