#pragma once

#include <span>
#include <vector>

#include "sim/remesh/remesh_mesh.h"

namespace incise::sim::remesh {

// The vertices of t in positive order with e tested against their circumsphere: true if e is
// strictly inside (symbolically perturbed by vertex id, so never on it).
bool in_circumsphere(const RemeshMesh& mesh, int t, int e);

// True if face k of tet t is locally Delaunay: on the boundary or constrained, or the vertex
// across it is outside t's circumsphere (perturbed).
bool is_locally_delaunay(const RemeshMesh& mesh, int t, int k);

enum class FlipKind { kNone, k23, k32, k44, k22 };

// How many flips of each kind: of[static_cast<int>(FlipKind::k23)], ...
struct FlipCounts {
  int of[5] = {0, 0, 0, 0, 0};
};

// If face k of tet t is unconstrained and not locally Delaunay, replaces it by one flip and
// returns its kind; the new tets' ids are written to `created`. With p the vertex of t opposite the
// face and d the vertex across it, the flip is the one the segment pd asks for (Joe 1991):
//   2-3  pd crosses the face: the face is replaced by the edge pd;
//   3-2  pd passes an edge ab of the face that exactly three tets share: ab is replaced by the
//        face across it;
//   4-4  p, d and an edge ab are coplanar and four tets share ab: ab is replaced by pd in the
//        plane (allowed on a label interface if both sub-faces of the plane have one parent);
//   2-2  the same on the boundary, where only two tets share ab (the two boundary sub-faces
//        must have one parent: the flip re-triangulates inside one facet).
// Returns kNone (and changes nothing) if no flip applies, a new tet would not be positively
// oriented (the union is not convex), or the flip would remove a constrained face or an edge
// of a constrained surface.
FlipKind flip_face(RemeshMesh& mesh, int t, int k, std::vector<int>* created);

// The flip queue of Joe / Edelsbrunner-Shah: tests every face of the tets `seeds`, flips the
// non locally Delaunay ones, and queues every face of every tet a flip creates, until none is
// left. Returns the number of flips; adds them up by kind in `counts` if given. After inserting one
// vertex into a constrained Delaunay mesh this restores the constrained Delaunay property.
int restore_delaunay(RemeshMesh& mesh, std::span<const int> seeds, FlipCounts* counts = nullptr);

// The initial state for remeshing: flips the whole mesh towards its constrained Delaunay
// tetrahedralisation (perturbed by vertex id). Flipping an arbitrary 3D mesh can get stuck
// (Joe 1989), and does for the lattice of a box mesh; every face still not locally Delaunay
// then is frozen: made a constrained face of its own (constrain_face), same label on both
// sides. The result is constrained Delaunay for its vertices and its (extended) constrained
// faces, and as such unique; so removing every inserted vertex returns exactly to it (not to
// an arbitrary input mesh, which need not be Delaunay). Frozen faces can be split by insertions
// like any constrained face; their free edges cannot (see insert_on_edge).
// Returns the number of frozen faces.
int make_constrained_delaunay(RemeshMesh& mesh);

}  // namespace incise::sim::remesh
