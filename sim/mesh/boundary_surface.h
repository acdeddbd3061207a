#pragma once

#include <array>
#include <cstdint>
#include <set>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// The boundary of a tet mesh: faces that belong to exactly one tet, oriented counter-clockwise
// seen from outside (their right-hand normal points out of the mesh, as for boundary_faces).
// Surface vertices are numbered locally so that a renderer or a contact search touches only
// surface nodes.
struct BoundarySurface {
  std::vector<int> nodes;  // mesh node index of each surface vertex, ascending
  Triangles faces;         // #F by 3, indices into `nodes` (local vertex numbers)
  std::vector<int> tets;   // #F: the tet each face belongs to (its tissue label, for a tool)
};

// The boundary of mesh (topology only: mesh.tets, positively oriented at rest).
// Throws std::invalid_argument for a face shared by more than two tets (see boundary_faces).
BoundarySurface boundary_surface(const TetMesh& mesh);

// The boundary of a tet mesh kept up to date through local changes, for meshes that a cut or a
// refinement changes a few tets of thousands at a time: a table of every face and the tets that
// share it, and the boundary faces ordered by (tet, local face), so that surface() equals
// boundary_surface(mesh) (face for face, in the same order) without sorting all the mesh's faces
// again. A change costs the changed tets' faces, and surface() the boundary's size plus a pass
// over the nodes.
class BoundaryTracker {
 public:
  BoundaryTracker() = default;
  // The faces of tets. Throws std::invalid_argument for a face shared by more than two tets, or
  // for a node index of 2^21 or more (faces are keyed by their three nodes in 64 bits).
  explicit BoundaryTracker(const Tets& tets);

  // Rows `changed` (each at most once) of tets hold other tets than at the last call (or are new
  // rows: the mesh may only have grown); every other row is as it was. Throws as the constructor,
  // with the tracker then unusable (rebuild it).
  void update(const Tets& tets, std::span<const int> changed);

  // The surface, numbered as boundary_surface numbers it; num_nodes is the mesh's node count.
  BoundarySurface surface(int num_nodes) const;

 private:
  struct Face {
    int count = 0;
    std::array<int, 2> tet{-1, -1};
    std::array<int, 2> local{-1, -1};
  };
  void add(int t);
  void remove(int t);

  Tets tets_;  // the tets as last seen
  std::unordered_map<std::uint64_t, Face> faces_;
  std::set<std::pair<int, int>> boundary_;  // (tet, local face) of the faces with one tet
};

// Positions and area-weighted unit vertex normals of the surface vertices at positions x
// (#mesh nodes by 3 [m]): V.row(j) = x.row(surface.nodes[j]), N.row(j) = the normalised sum of the
// (twice) area vectors of the faces at vertex j, so large faces weigh more. A vertex whose faces'
// area vectors cancel or vanish (degenerate, collapsed surface) gets N.row(j) = 0, not NaN (for
// finite x).
// V and N are resized to #surface vertices by 3 (reuse them between calls: no allocation once
// sized).
void surface_vertices(const BoundarySurface& surface, const Points& x, Points& V, Points& N);

}  // namespace incise::sim
