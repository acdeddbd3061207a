#pragma once

#include <random>

#include "sim/mesh/tet_mesh.h"
#include "sim/remesh/insertion.h"
#include "sim/remesh/remesh_mesh.h"

namespace incise::sim::remesh::testing {

// The unit box on 4 x 4 x 4 cells (320 tets), all label 0.
TetMesh unit_box();
// The same box with label 1 where the tet centroid has x >= 0.5: an interface plane at x = 0.5
// made of grid faces.
TetMesh two_label_box();

// The two-label box with its interior nodes off the interface moved at random by up to a fifth
// of a cell per coordinate: points in general position (no cospherical ties), while the
// boundary and the interface stay exactly planar.
TetMesh jittered_two_label_box(unsigned seed);

// One random insertion of the given kind on the mesh (0 in a tet, 1 on a face, 2 on an edge,
// 3 on a constrained face, 4 on a constrained edge); positions on faces and edges use dyadic
// parameters so that points on axis-aligned constrained surfaces are exactly on them.
InsertResult random_insertion(RemeshMesh& mesh, int kind, std::mt19937& rng);

}  // namespace incise::sim::remesh::testing
