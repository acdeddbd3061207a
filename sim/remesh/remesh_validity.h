#pragma once

#include <array>
#include <string>
#include <vector>

#include "sim/remesh/remesh_mesh.h"

namespace incise::sim::remesh {

// Checks every invariant of a constrained Delaunay RemeshMesh; returns "" if all hold, else a
// description of the first violation found:
//  - conforming: tet vertices alive and distinct, face adjacency symmetric, no face in more
//    than two tets, each alive vertex's vertex_tet holds it;
//  - every tet positively oriented (exact);
//  - constrained faces: every boundary face and every face between labels is constrained,
//    both sides of a face agree on its facet, and the sub-faces of each facet are exactly
//    coplanar with it and cover its area (relative 1e-12): the surface is unchanged;
//  - Delaunay: every unconstrained interior face is locally Delaunay (perturbed in-sphere), and
//    within each facet the sub-faces are 2D Delaunay (each edge between two sub-faces of one
//    facet passes the in-sphere test of a tet on the side walked from).
std::string check_remesh_mesh(const RemeshMesh& mesh);

// The mesh as a canonical set: one row per alive tet, its sorted vertex ids then its label,
// rows sorted. Two meshes with the same vertex ids are the same mesh iff these are equal.
std::vector<std::array<int, 5>> canonical_tets(const RemeshMesh& mesh);

// Sum of the signed rest volumes of the alive tets [m^3].
Real remesh_volume(const RemeshMesh& mesh);

}  // namespace incise::sim::remesh
