#pragma once

// Step 5 of cut_mesh: duplicating the nodes of the crack faces, one copy per side.

#include <array>
#include <vector>

#include "sim/core/types.h"

namespace incise::sim::cut {

using FaceKey = std::array<int, 3>;  // a face's node indices, ascending

// A node moved to a copy in one tet: tets(tet, corner) becomes node.
struct NodeRepoint {
  int tet = 0;
  int corner = 0;
  int node = 0;
};

// For each node of the crack faces (opened, sorted and unique), the groups of its tets that are
// connected through faces holding the node that are not crack faces. The group of the lowest tet
// slot keeps the node; every other group gets a new node numbered from first_copy on, recorded in
// copy_of (its source node) and repoints (its tets' corners). Reads tets.
// Where the crack is ragged (a partially cut tet leaves a gap in the crack around a node), a
// node or copy could end up pinched: its boundary faces forming two fans that touch only at the
// node, a non-manifold surface. The crack faces at such a node are closed again (removed from
// opened) and the grouping redone, until no node is pinched.
void split_crack_nodes(const Tets& tets, std::vector<FaceKey>& opened, int first_copy,
                       std::vector<int>& copy_of, std::vector<NodeRepoint>& repoints);

}  // namespace incise::sim::cut
