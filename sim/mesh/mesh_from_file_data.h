#pragma once

#include <string>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// The TetMesh of the nodes and tets read from a mesh file, after the checks that every reader
// shares:
//   nodes      #nodes by 3 positions [m] as read (finite)
//   tets       #tets by 4 indices into nodes (in range; the reader checked)
//   labels     #tets labels
//   tet_lines  #tets line numbers where each tet was read, for the errors
//   file       the file name for the errors
// A tet that repeats a node or is degenerate (is_degenerate in mesh_quality.h) throws MeshFileError
// at its line. A negatively oriented tet is made positive by swapping its last two nodes (writers
// differ in their convention; the orientation carries no information). Nodes that no tet uses (gmsh
// keeps geometry points, for example) are dropped, the others keep their order: a node without a
// tet would have no mass in a simulation.
TetMesh mesh_from_file_data(const Points& nodes, Tets tets, Eigen::VectorXi labels,
                            const std::vector<int>& tet_lines, const std::string& file);

}  // namespace incise::sim
