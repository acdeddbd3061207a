#pragma once

// How one tet is cut: which of its edges the cut surface crosses and which of its vertices lie on
// it decide whether the tet is cut through (its vertices fall into two sides, A and B, and the
// crossed edges are exactly those joining A to B) and into how many pieces. Knee Arthroscopy VR
// (section VII.B, Fig. 14) lists the completely cut cases with minimal new elements; the vertex
// snapping of find_edge_cuts adds the cases where the surface passes through a vertex or an edge.
//
//   case           A|B (on)   edges cut   pieces (A + B)   new tets
//   tip            1|3 (0)    3           1 + 3            3
//   split          2|2 (0)    4           3 + 3            5
//   through_vertex 1|2 (1)    2           1 + 2            2
//   through_edge   1|1 (2)    1           1 + 1            1
//
// A tet with 3 vertices on the surface is cut along that face without subdivision (see
// cut_mesh). Every other pattern (1, 2 or 3 edges on one face, 5 or 6 edges, a folded surface)
// is a partial cut: the blade is still inside the tet, and the tet is only refined where its
// neighbours need it.

#include <array>
#include <span>
#include <vector>

namespace incise::sim::cut {

enum class TetCutCase { none, tip, split, through_vertex, through_edge };

struct TetCutPattern {
  TetCutCase kind = TetCutCase::none;
  // Per local vertex: 0 (side A), 1 (side B) or -1 (on the surface); all 0 for `none`. Side A
  // holds local vertex 0 unless vertex 0 is on the surface (then the first vertex off it).
  std::array<int, 4> side = {0, 0, 0, 0};
};

// The case of a tet whose local edges kTetEdges[e] (sim/mesh/tet_adjacency.h) are crossed where
// edge_cut[e] and whose local vertex k lies on the surface where on_surface[k]. Edges at a vertex
// on the surface are ignored (the surface meets them at that vertex).
TetCutPattern classify_tet_cut(const std::array<bool, 6>& edge_cut,
                               const std::array<bool, 4>& on_surface);

// An edge (a, b) of the mesh split at its new node `middle`.
struct EdgeSplit {
  int a = 0;
  int b = 0;
  int middle = 0;
};

// The tets that tet (node indices) becomes when its edges in splits are bisected one after the
// other, appended to out. Bisecting edge (a, b) replaces every current piece holding both a and b
// by the two pieces with a, then b, replaced by the middle node; a middle node on the open
// segment keeps each piece's orientation. Splits that are not edges of tet are skipped.
// Conforming: two tets sharing a face split it identically when both get the same splits in the
// same order, so cut_mesh orders every tet's splits by the global key (min node, max node).
// With the splits of a complete cut in that order, the pieces are the minimal ones of the table.
void bisect_tet(const std::array<int, 4>& tet, std::span<const EdgeSplit> splits,
                std::vector<std::array<int, 4>>& out);

}  // namespace incise::sim::cut
