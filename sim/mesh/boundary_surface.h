#pragma once

#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// The boundary of a tet mesh: faces that belong to exactly one tet, oriented counter-clockwise
// seen from outside (their right-hand normal points out of the mesh, as for boundary_faces).
// Surface vertices are numbered locally so that a renderer or a contact search touches only
// surface nodes.
struct BoundarySurface {
  std::vector<int> nodes;  // mesh node index of each surface vertex, ascending
  Triangles faces;         // #F by 3, indices into `nodes` (local vertex numbers)
  std::vector<int> tets;   // #F: the tet each face belongs to (its tissue label, for a tool)
};

// The boundary of mesh (topology only: mesh.tets, positively oriented at rest).
// Throws std::invalid_argument for a face shared by more than two tets (see boundary_faces).
BoundarySurface boundary_surface(const TetMesh& mesh);

// Positions and area-weighted unit vertex normals of the surface vertices at positions x
// (#mesh nodes by 3 [m]): V.row(j) = x.row(surface.nodes[j]), N.row(j) = the normalised sum of the
// (twice) area vectors of the faces at vertex j, so large faces weigh more. A vertex whose faces'
// area vectors cancel or vanish (degenerate, collapsed surface) gets N.row(j) = 0, not NaN (for
// finite x).
// V and N are resized to #surface vertices by 3 (reuse them between calls: no allocation once
// sized).
void surface_vertices(const BoundarySurface& surface, const Points& x, Points& V, Points& N);

}  // namespace incise::sim
