#pragma once

// Measurements the mesher tests assert on, computed here from the arrays alone so that the tests
// do not trust the code under test, and the checks every generated mesh must pass.

#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/cgal/mesh_generation.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim::testing {

// The smallest of the six interior dihedral angles [degrees] over all tets.
Real min_dihedral_angle_deg(const Points& points, const Tets& tets);

// The number of face-connected components of the tets.
int num_components(const Tets& tets);

// The nodes on the boundary (in a face that belongs to one tet), ascending.
std::vector<int> boundary_nodes(const Tets& tets);

// Sum of the signed volumes [m^3] of the tets whose label is `label`.
Real labelled_volume(const Points& points, const Tets& tets, const Eigen::VectorXi& labels,
                     int label);

// Every mesh Mesh_3 gives back after perturbation and exudation should have no dihedral angle
// below this [degrees] (measured 12-16 degrees: see the figures the tests print).
inline constexpr Real kMinDihedralBound = 10;

// Criteria with cell_size = facet_size = size [m] and facet_distance = distance [m].
MeshingCriteria criteria(Real size, Real distance);

// The cube of half side `half` [m] around centre.
Box3 box_around(const Vec3& centre, Real half);

// The invariants of every generated mesh (gtest expectations): tets of positive volume, nodes
// inside bounds, at rest (x = rest, v = 0), min dihedral angle above kMinDihedralBound.
void expect_valid(const TetMesh& mesh, const Box3& bounds);

// Prints a line of figures (sizes, volume against reference, min dihedral angle) for the report.
void print_figures(const char* name, const TetMesh& mesh, Real volume, Real reference);

}  // namespace incise::sim::testing
