#pragma once

// Simplification of the slivers a cut leaves (Knee Arthroscopy VR, section VII.C): half-edge
// collapses of edges of the poor tets near the cut, each accepted only if it passes the paper's
// checks:
//   - inversion: every tet around the removed node stays positively oriented in the rest AND the
//     current configuration once the node moves onto the kept one;
//   - topology: the link condition (Dey, Edelsbrunner et al., "Topology preserving edge
//     contraction"): Lk(a) ∩ Lk(b) = Lk(ab), with the boundary closed by a virtual vertex joined
//     to every boundary face. It refuses both of the paper's Fig. 20 cases (a hole beside the edge
//     that would close, two parts that would be left joined by an edge or a node);
//   - boundary error: a removed boundary node must be collapsed onto a boundary node, and the
//     boundary must stay within boundary_tolerance of where it was: the kept node within it of
//     the planes of the removed node's old boundary faces, and the removed node within it of the
//     planes of the new ones (the paper's "projected distance to the original triangle", rest
//     configuration). A small tolerance keeps the rest volume (a collapse of an interior node
//     re-cones its star from the kept node: the same polyhedron, the same volume exactly);
//   - progress: the worst quality of the tets around the removed node must improve, so that a
//     collapse never makes a sliver elsewhere.
// The kept node does not move (a half-edge collapse: the paper's "vertex replacement" on the
// surface node, without the midpoint option, which would move the boundary).
//
// Quality of a tet: its smallest altitude over its longest edge (0 for a flat tet, sqrt(2/3) for
// the regular one, 1/sqrt(6) ~ 0.41 for the 6 tets of a box mesh's cube).

#include <span>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim::cut {

struct SimplifyOptions {
  Real min_quality = 0.1;          // tets below this are slivers to remove
  Real boundary_tolerance = 1e-9;  // [m] allowed boundary displacement (see above)
  int max_passes = 5;              // sweeps over the slivers left
};

struct SimplifyReport {
  int collapses = 0;
  int rejected_inversion = 0;
  int rejected_topology = 0;
  int rejected_boundary = 0;
  int rejected_quality = 0;     // no progress
  int rejected_pinned = 0;      // the node to remove is pinned
  Real min_quality_before = 0;  // over the region's tets
  Real min_quality_after = 0;
  int slivers_left = 0;  // region tets still below min_quality
  // The compaction after the collapses: old tet slot / node -> new one, or -1 where removed.
  std::vector<int> tet_map;
  std::vector<int> node_map;
};

// Smallest altitude over longest edge of the tet (a, b, c, d), signed like its volume.
Real tet_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// Whether contracting edge (a, b) keeps the topology of tets (the link condition above).
// Scans all tets (for tests and one-off checks; simplify_cut_region uses the nodes' stars).
bool link_condition_holds(const Tets& tets, int a, int b);

// Removes the slivers among the region's tets (slots, e.g. CutReport::changed_tets) and the tets
// sharing a node with them, by checked half-edge collapses. The mesh is then compacted (removed
// tets and nodes erased, order kept; see the report's maps): a model should call
// update_topology. Nodes with pinned[i] != 0 are never removed (e.g. a condensed far field's
// nodes, whose tets must not change); empty: none. Throws std::invalid_argument if a region slot
// is out of range or pinned is neither empty nor #nodes long.
SimplifyReport simplify_cut_region(TetMesh& mesh, std::span<const int> region,
                                   const SimplifyOptions& options = {},
                                   std::span<const char> pinned = {});

}  // namespace incise::sim::cut
