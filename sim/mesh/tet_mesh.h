#pragma once

#include "sim/core/types.h"

namespace incise::sim {

// A tetrahedral mesh and its per-node state, as structure of arrays. Tets are positively
// oriented in the rest configuration: signed_volume(a, b, c, d) > 0, i.e. d lies on the side
// that (b - a) x (c - a) points to.
struct TetMesh {
  Points rest;             // #nodes by 3 rest positions [m]
  Points x;                // #nodes by 3 current positions [m]
  Points v;                // #nodes by 3 velocities [m/s]
  Tets tets;               // #tets by 4 node indices into the node arrays
  Eigen::VectorXi labels;  // #tets tissue labels (0 = the default tissue)

  int num_nodes() const { return static_cast<int>(rest.rows()); }
  int num_tets() const { return static_cast<int>(tets.rows()); }
};

// A mesh at rest: x = rest, v = 0, labels all 0 unless given.
//   rest    #nodes by 3 rest positions [m]
//   tets    #tets by 4 node indices
//   labels  #tets tissue labels, or empty for all 0
// Throws std::invalid_argument if an index is outside [0, #nodes), a tet repeats a node or
// labels has the wrong size. Orientation is not checked here (see tet_volumes).
TetMesh make_tet_mesh(Points rest, Tets tets, Eigen::VectorXi labels = {});

// Signed volume [m^3] of the tet (a, b, c, d): (b - a) . ((c - a) x (d - a)) / 6; positive for a
// positively oriented tet, zero for a flat one.
inline Real signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a)) / Real(6);
}

// #tets signed volumes [m^3] of tets over the node positions points (#nodes by 3 [m]).
VecX tet_volumes(const Points& points, const Tets& tets);

// Sum of the signed tet volumes [m^3].
Real total_volume(const Points& points, const Tets& tets);

}  // namespace incise::sim
