#pragma once

#include <vector>

#include "sim/core/types.h"

namespace incise::sim {

// Connectivity derived from the tets alone (no positions). Local numbering, used throughout sim/:
//   edge e of a tet joins local nodes kTetEdges[e]: (0,1) (0,2) (0,3) (1,2) (1,3) (2,3);
//   face k of a tet is the face opposite local node k, kTetFaces[k], ordered so that its normal
//   (by the right-hand rule) points out of a positively oriented tet.
inline constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
inline constexpr int kTetFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

using TetEdgeIndices = Eigen::Matrix<int, Eigen::Dynamic, 6, Eigen::RowMajor>;

// The unique edges of tets, #edges by 2 node indices, each row (i, j) with i < j, rows sorted
// lexicographically.
Edges unique_edges(const Tets& tets);

// #tets by 6: row t, column e is the row of edges holding local edge e of tet t.
//   edges  as returned by unique_edges(tets) (sorted; looked up by binary search)
// Throws std::invalid_argument if an edge of tets is missing from edges.
TetEdgeIndices tet_edge_indices(const Tets& tets, const Edges& edges);

// The tets around each node in compressed rows: the tets incident to node i are
// tets[offsets[i]] .. tets[offsets[i + 1] - 1], in increasing order. offsets has #nodes + 1
// entries; a node no tet uses has none.
struct NodeTets {
  std::vector<int> offsets;
  std::vector<int> tets;
};
NodeTets node_tets(const Tets& tets, int num_nodes);

// #tets by 4: entry (t, k) is the tet sharing face k (opposite local node k) of tet t, or -1 if
// that face is on the boundary.
// Throws std::invalid_argument if a face is shared by more than two tets (non-manifold input).
Tets face_neighbours(const Tets& tets);

// The faces that belong to exactly one tet, #faces by 3 node indices, oriented outwards for
// positively oriented tets (kTetFaces); ordered by tet, then local face. With face_tets, also the
// tet each face belongs to (#faces entries).
// Throws std::invalid_argument like face_neighbours.
Triangles boundary_faces(const Tets& tets, std::vector<int>* face_tets = nullptr);

}  // namespace incise::sim
