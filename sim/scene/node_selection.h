#pragma once

#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// The tolerance [m] by which selection boxes are widened: 1e-6 of the diagonal of the points'
// bounding box, so that a box drawn exactly on a mesh face picks the face's nodes despite
// round-off in their coordinates, while staying far below any element size.
Real selection_tolerance(const Points& points);

// Indices (increasing) of the points inside box widened by tolerance on every side:
// box.min - tolerance <= p <= box.max + tolerance component-wise.
//   points  #nodes by 3 positions [m]
std::vector<int> nodes_in_box(const Points& points, const Box3& box, Real tolerance);

// The nodes a body held at rest keeps still: per node 1 where a constraint of scene holds it
// (the live block and calibration, which take only "fix": "xyz" constraints). Throws
// SceneError("constraints[k]", ...) for a constraint that holds only some axes or displaces its
// nodes, SceneError("constraints[k].where", "selects no node") for one that selects none.
struct Scene;
std::vector<char> held_at_rest(const Scene& scene, const TetMesh& mesh);

}  // namespace incise::sim
