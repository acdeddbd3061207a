#pragma once

// Point location in a RemeshMesh by a visibility walk with exact orientation tests, and
// insertion at the point found.

#include "sim/remesh/insertion.h"
#include "sim/remesh/remesh_mesh.h"

namespace incise::sim::remesh {

enum class LocationKind {
  kInTet,             // strictly inside `tet`
  kOnFace,            // on face `face` of `tet`, strictly inside the face (exactly coplanar)
  kOnEdge,            // on the edge (a, b) of `tet`, strictly between a and b (exactly collinear)
  kOnVertex,          // at vertex a
  kBeyondConstraint,  // beyond face `face` of `tet`, which is constrained or on the boundary
  kNotFound,          // the walk did not settle within its step budget
};

struct Location {
  LocationKind kind = LocationKind::kNotFound;
  int tet = -1;
  int face = -1;
  int a = -1, b = -1;
};

// Walks from the alive tet `start` towards p: from the current tet, across a face that p lies
// strictly beyond (exact orientation), trying the faces in an order that rotates every step (a
// stochastic visibility walk, which cannot cycle forever on a Delaunay mesh). Stops at the tet
// whose closure holds p, or at the first constrained or boundary face that p lies beyond: a
// point across a surface or a label interface is not looked for on the other side.
//   max_steps  walk budget; <= 0 means the number of tets.
Location locate(const RemeshMesh& mesh, int start, const Vec3& p, int max_steps = 0);

// Inserts p where `where` says (kInTet, kOnFace or kOnEdge: insert_in_tet, insert_on_face,
// insert_on_edge); any other kind returns kNotInside and leaves the mesh unchanged.
InsertResult insert_at(RemeshMesh& mesh, const Location& where, const Vec3& p);

}  // namespace incise::sim::remesh
