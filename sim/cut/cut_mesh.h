#pragma once

// Cutting a tet mesh by subdivision (Knee Arthroscopy VR, section VII): the tets that the cut
// surface crosses completely are split along it with the minimal pieces of their case
// (tet_split.h), and the mesh opens along the new faces: nodes on the crack get one copy per side,
// so that the two sides no longer share a node there and the tissue can part.
//
// Steps of one cut (a blade sweep, or a whole path, applied at once):
//   1. crossings of the surface with the mesh edges in the CURRENT configuration, snapped to the
//      end nodes within `snap` of them (edge_cuts.h);
//   2. the case of each tet (classify_tet_cut); the crossed edges of completely cut tets are
//      split: the new node sits at the crossing's t in BOTH the rest and the current positions,
//      its velocity interpolated likewise (the cut is where the trainee sees it, and the rest
//      state stays force-free);
//   3. every tet holding a split edge is bisected along its split edges in the global order of
//      (min node, max node): cut tets into their case's pieces, partially cut neighbours only so
//      that they conform (no hanging node). A face is split the same way from both of its tets,
//      so the result is conforming (crack-free as Knee Arthroscopy VR, section VII.B.1, asks);
//   4. crack faces: the faces between the two sides' pieces of a cut tet, and mesh faces whose 3
//      nodes are on the surface when the surface separates the two tets' opposite nodes;
//   5. each node of a crack face gets one copy per group of its tets that stay connected through
//      faces that are not crack faces. A node at the crack front (where the blade stopped) keeps
//      its tets connected around the front, so it is not duplicated: the crack closes there.
//      Where a partially cut tet leaves a gap in the crack right at a node, that node would be
//      pinched (two boundary sheets touching at a point); the crack faces there close again
//      (CutReport::faces_closed), so that the boundary stays a manifold surface.
//
// Cost: one pass over all edges (unique_edges, sorted) and tets, and face_neighbours when a node
// snaps; meant for a cut event or a local region (cut_mesh_active, as ProgressiveCutter uses it).
//
// The partially cut tets (the blade still inside) are split temporarily by split_front_tets
// (front_split.h), frame by frame through ProgressiveCutter (progressive_cutter.h); slivers are
// removed afterwards by simplify_cut_region (simplify_cut.h).

#include <array>
#include <span>
#include <vector>

#include "sim/core/types.h"
#include "sim/cut/cut_surface.h"
#include "sim/cut/tet_split.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim::cut {

struct CutOptions {
  // Crossings within this fraction of an edge from an end node move to that node, so that no
  // piece is thinner than snap times its tet (in (0, 0.5)).
  Real snap = 0.05;
};

// Where a new node comes from: on the edge (a, b) at (1 - t) a + t b, or, for b = -1, a copy of
// node a on the other side of the crack (a may itself be a new node of the same cut).
struct NodeOrigin {
  int a = -1;
  int b = -1;
  Real t = 0;
};

struct CutReport {
  // Completely cut tets per case, indexed by TetCutCase (entry `none` stays 0).
  std::array<int, 5> cases{};
  int faces_opened = 0;    // mesh faces with 3 nodes on the surface opened without subdivision
  int refined_tets = 0;    // partially cut tets bisected only to conform with cut neighbours
  int snapped_nodes = 0;   // mesh nodes a crossing was moved to (within snap of an end node)
  int faces_closed = 0;    // crack faces closed again where the crack would pinch a node
  int first_new_node = 0;  // nodes [first_new_node, #nodes) are new
  std::vector<NodeOrigin> new_nodes;  // origin of node first_new_node + k
  // Tet slots that appeared or were replaced (a cut tet keeps its slot for its first piece, its
  // other pieces are appended; tets whose node moved to a crack copy are replaced), ascending.
  // With every slot alive, this is the `changed` of Model::update_elements.
  std::vector<int> changed_tets;
  // The crack's new boundary faces, both sides, oriented outwards, with the final node indices.
  Triangles crack_faces;
};

// Cuts mesh along surface (current configuration) in place: nodes are appended to rest, x and v,
// tets replaced and appended with their parent's label. Tets stay positively oriented in the rest
// configuration (each bisection at t gives its two pieces the fractions t and 1 - t, both at least
// snap, of the piece it splits) and the total rest volume is unchanged.
// Throws std::invalid_argument, with mesh unchanged, if the mesh's arrays disagree in size, a tet
// holds a node index out of range or options.snap is outside (0, 0.5).
CutReport cut_mesh(TetMesh& mesh, const CutSurface& surface, const CutOptions& options = {});

// cut_mesh restricted to the tets where active[t] != 0 (#tets flags, or empty for all): only they
// may be cut through or have a face opened; the others are only bisected where an active
// neighbour's split edge needs it (conformity). ProgressiveCutter uses it on a local region whose
// outer layer is inactive, so that every crack node's full star lies inside the region.
// Throws like cut_mesh, and if active has neither 0 nor #tets entries.
CutReport cut_mesh_active(TetMesh& mesh, const CutSurface& surface, std::span<const char> active,
                          const CutOptions& options = {});

}  // namespace incise::sim::cut
