#pragma once

// Where the cut surface crosses the mesh edges, in the current configuration, with the snapping
// that keeps the subdivision free of slivers: a crossing at t < snap or t > 1 - snap along an
// edge is moved to the nearer end node, which is then "on the surface" (and later duplicated
// along the crack like a new node). Every edge at a node on the surface counts as not crossed:
// the surface meets it at that node. An edge the surface crosses more than once (a surface that
// folds back within one edge) counts as not crossed either; the cut stops short of it.

#include <vector>

#include "sim/core/types.h"
#include "sim/cut/cut_surface.h"

namespace incise::sim::cut {

struct EdgeCut {
  int a = 0;   // the edge's smaller node index
  int b = 0;   // its larger one
  Real t = 0;  // the crossing at (1 - t) x_a + t x_b, t in [snap, 1 - snap]
};

struct EdgeCuts {
  std::vector<EdgeCut> cuts;     // sorted by (a, b)
  std::vector<char> on_surface;  // #nodes, 1 for a node snapped onto the surface
};

// The crossings of surface with edges (#edges by 2 node indices, as from unique_edges) at node
// positions x (#nodes by 3 [m]).
//   snap  in (0, 0.5): the fraction of an edge within which a crossing moves to the end node
// Throws std::invalid_argument for snap outside (0, 0.5).
EdgeCuts find_edge_cuts(const Points& x, const Edges& edges, const CutSurface& surface, Real snap);

// The crossing of edge (a, b) in cuts (either order), or nullptr.
const EdgeCut* find_cut(const EdgeCuts& cuts, int a, int b);

}  // namespace incise::sim::cut
