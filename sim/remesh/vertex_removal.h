#pragma once

#include "sim/remesh/remesh_mesh.h"

namespace incise::sim::remesh {

enum class RemoveStatus {
  kRemoved,
  kOriginalVertex,   // vertices of the original mesh are never removed
  kCannotRemoveNow,  // the hole could not be re-tetrahedralised here; retry later
};

struct RemoveResult {
  RemoveStatus status = RemoveStatus::kCannotRemoveNow;
  // Tets removed and created. Non-empty also for kCannotRemoveNow when a re-tetrahedralisation
  // was tried and rolled back: the same tets then sit in new slots.
  TetChanges changes;
};

// Decimation by vertex removal (Renze and Oliver's hole filling), the reverse of insertion:
// the star of v is removed and each side of it (the star is cut into sides by the constrained
// faces through v: one side for an interior vertex, one per label region or boundary wedge
// otherwise) is re-tetrahedralised by gift wrapping from its link faces, taking for each open
// face the link vertex whose circumsphere with the face holds no other link vertex (perturbed
// in-sphere). Faces that close on a constrained surface through v become that surface's new
// sub-faces, so the original face that v split is merged back. For a vertex of a
// constrained Delaunay mesh the result is the constrained Delaunay mesh without v; hence
// removing every inserted vertex restores the initial mesh exactly (see
// make_constrained_delaunay). The filling is checked (every link face closed, all tets
// positive, volume and constrained area conserved, locally Delaunay) and otherwise refused with
// kCannotRemoveNow, leaving the mesh as it was.
//   min_altitude  the floor on the filling's tets [m]: a filling with a tet lower than this is
//                 refused (kCannotRemoveNow, before any edit), so that decimation keeps the
//                 stable time step's floor as refinement does (RefinementSettings::
//                 floor_altitudes). 0: no floor.
RemoveResult remove_vertex(RemeshMesh& mesh, int v, Real min_altitude = 0);

}  // namespace incise::sim::remesh
