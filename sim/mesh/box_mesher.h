#pragma once

#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// A tetrahedral mesh of the box [0, size.x] x [0, size.y] x [0, size.z] (corner at the origin)
// on a grid of cells.x by cells.y by cells.z equal cells, at rest, all labels 0.
//   size   box edge lengths [m], each > 0
//   cells  cells per axis, each >= 1
// Each cell is split into 5 tets: a central tet on the 4 cell corners of even grid parity
// (i + j + k even) and one tet cut off at each of the other 4 corners. Every face diagonal thus
// joins two even nodes, so neighbouring cells agree on it (the mesh is conforming), and the
// diagonals alternate in direction from cell to cell. That alternation matters for the
// mass-spring model, whose springs are the tet edges: the 6-tet split around the main diagonal
// puts every diagonal spring in the same direction, which couples compression to shear (a cube
// under its own weight leans towards the (1,1,1) corner by about as much as it sags).
// All tets are positively oriented.
// Node (i, j, k) of the grid has index i + (cells.x + 1) * (j + (cells.y + 1) * k).
// Result: (cells.x+1)(cells.y+1)(cells.z+1) nodes, 5 cells.x cells.y cells.z tets.
// Throws std::invalid_argument for a non-positive size or cell count.
TetMesh make_box_mesh(const Vec3& size, const Vec3i& cells);

}  // namespace incise::sim
