#pragma once

// Local refinement of a surgical scene's tissue by edge bisection, and its undo (refine around
// the probe's contact and the grasper's jaws, coarsen again once the tool has gone: the online
// remeshing of Paloc 2006, on the plain TetMesh that cutting edits).
//
// Bisecting an edge (a, b) inserts a node m at its rest midpoint and splits every tet around the
// edge in two, (.., a, .., b, ..) into (.., a, .., m, ..) and (.., m, .., b, ..): the mesh stays
// conforming (every face of a split tet is split alike in its neighbour), the rest volume and
// the boundary surface do not change, and both halves keep the parent's orientation (m lies on
// the segment a b). The new node gets the midpoint of a's and b's positions and velocities: the
// deformed tet's own point, so an affinely deformed or moving body keeps its state exactly, and
// with lumped masses (V/4 per node and tet) the momentum and the centre of mass are unchanged.
//
// Which edge: Rivara's longest-edge propagation path. An edge is split only when it is the
// longest edge of every tet around it; otherwise the longer edge of the tet that has one is split
// first. Every tet is thus cut across its longest edge, which keeps the shapes bounded.
//
// Undo: the split of (a, b) at m is undone while m's star is still exactly the pairs
// (.., a, .., m, ..), (.., m, .., b, ..) with the same other two nodes (no cut has crossed it,
// no later split uses m): the first of each pair goes, m becomes a in the second. That restores
// the tets the split replaced, exactly; m's own displacement is lost (the coarse mesh cannot
// hold it).

#include <functional>
#include <span>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim::surgery {

// One split: node `mid` was inserted at the rest midpoint of the edge (a, b).
struct Bisection {
  int mid = -1;
  int a = -1;
  int b = -1;
};

struct BisectionSettings {
  Real edge_length = 0.004;  // split edges longer than this [m], > 0
  // A split is refused when a tet it makes would have a smaller rest altitude [m] (the explicit
  // step's floor: no split may make the tissue need a shorter step) or a smaller quality
  // (cut::tet_quality: smallest altitude over longest edge; the sliver bound of the cut
  // simplification).
  Real min_altitude = 0;
  Real min_quality = 0.1;
  int max_splits = 2000;  // per call, >= 0
};

struct BisectionReport {
  int splits = 0;
  // Edges left longer than edge_length: a split (or one on its propagation path) would break
  // the floor above or touch a frozen tet.
  int refused = 0;
  int tets_before = 0;
  int nodes_before = 0;
  // The slots whose tet was replaced or appended, ascending, and per changed slot the slot
  // (before the call) whose tet it is a part of: the state a damage tracker carries over.
  std::vector<int> changed;
  std::vector<int> parents;
  std::vector<Bisection> bisections;  // in the order made; new nodes are nodes_before, ...
};

// Splits every edge longer than settings.edge_length that passes within `radius` of `centre`
// (rest configuration [m]) by the propagation rule above, until none is left, every one left is
// refused, or max_splits is reached. Tets whose slot is frozen (frozen[s] != 0; empty: none) are
// never split, nor are the edges they hold. New nodes are appended (rest, x and v rows; x and v
// only when they have a row per node); a split tet keeps its slot for its first half and its
// second half is appended, with the same label.
// Throws std::invalid_argument for settings out of range, a non-finite centre or radius, or
// frozen of a size other than 0 or #tets.
BisectionReport refine_ball(TetMesh& mesh, const Vec3& centre, Real radius,
                            const BisectionSettings& settings, std::span<const char> frozen = {});

struct CoarsenReport {
  int undone = 0;
  // Where each old tet slot and node went after the compaction (removed tets and nodes erased,
  // order kept), -1 where removed. Empty when nothing was undone.
  std::vector<int> tet_map;
  std::vector<int> node_map;
};

// Undoes, newest first, every split in `bisections` whose node's rest point keep() rejects and
// whose star is still the split's (above), then compacts the mesh. `bisections` is updated: the
// undone go, the others are renumbered (and dropped if a node of theirs is gone).
// Throws std::invalid_argument for a split whose nodes are out of range.
CoarsenReport undo_bisections(TetMesh& mesh, std::vector<Bisection>& bisections,
                              const std::function<bool(const Vec3& rest)>& keep);

// Renumbers splits after another compaction (e.g. the cut simplification's node_map): a split
// with a removed node is dropped.
void remap_bisections(std::vector<Bisection>& bisections, std::span<const int> node_map);

}  // namespace incise::sim::surgery
