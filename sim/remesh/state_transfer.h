#pragma once

// State transfer to a new vertex (Paloc 2006, "Online remeshing of volumetric MSS", Figure 4): a
// vertex inserted at rest point p inside the rest tet T (the tet that held p before the
// insertion) gets every nodal attribute a (deformed position, velocity, ...) as
// a = sum_i w_i a_i, with w the barycentric coordinates of p in T's rest corners and a_i the
// values at T's nodes. Linear in the nodal values, so an affine field a(X) = A X + b is
// reproduced exactly (up to rounding): sum_i w_i (A X_i + b) = A p + b since sum_i w_i X_i = p
// and sum_i w_i = 1. The remesher reports, for each insertion, T's vertices and w; the caller
// applies them to its models.

#include <array>
#include <functional>
#include <vector>

#include "sim/core/types.h"
#include "sim/remesh/insertion.h"
#include "sim/remesh/point_location.h"
#include "sim/remesh/remesh_mesh.h"
#include "sim/remesh/vertex_removal.h"

namespace incise::sim::remesh {

using Weights4 = Eigen::Matrix<Real, 4, 1>;

// Barycentric coordinates w of p in the tet `corners` (any orientation): p = sum_i w_i
// corners[i], sum_i w_i = 1; all in [0, 1] iff p is in the tet. Throws std::invalid_argument if
// the tet is flat (|6 V| <= kDegenerateTetRelativeVolume * longest edge^3).
Weights4 barycentric(const std::array<Vec3, 4>& corners, const Vec3& p);

// sum_i w_i values[i].
Vec3 interpolate(const std::array<Vec3, 4>& values, const Weights4& w);
Real interpolate(const std::array<Real, 4>& values, const Weights4& w);
// sum_i w_i values.row(rows[i]), for a #nodes by 3 attribute (positions, velocities, ...).
Vec3 interpolate_rows(const Points& values, const std::array<int, 4>& rows, const Weights4& w);

// The displacement x - rest of a tet mesh at rest point p: barycentric in the tet holding p, or,
// for a point outside the mesh (just outside a coarser mesh of the same shape), in the tet whose
// smallest weight is largest, the field extrapolated linearly. alive: per tet, 0 to skip (nullptr:
// every tet). A scan of all tets: for comparing fields in benchmarks and tests, not for a step.
Vec3 displacement_at(const Points& rest, const Points& x, const Tets& tets,
                     const std::vector<char>* alive, const Vec3& p);

// An insertion as the models need it.
struct InsertedVertex {
  int vertex = -1;
  Vec3 rest_point = Vec3::Zero();
  // The vertex ids of the tet that held the point before the insertion (for a point on a face
  // or an edge, one of the tets around it: the weights of the other corners are then zero up to
  // rounding), and the point's barycentric coordinates in their rest positions.
  TetVertices host{};
  Weights4 weights = Weights4::Zero();
};

// Called after every edit that the refinement and decimation drivers make, with the tets it
// removed and created, so that models can be updated locally. on_removal is called for every
// removal attempt: its changes are non-empty also for kCannotRemoveNow when a filling was tried
// and rolled back (the same tets then sit in new slots). Either may be empty.
struct RemeshListener {
  std::function<void(const InsertedVertex&, const TetChanges&)> on_inserted;
  std::function<void(int vertex, const RemoveResult&)> on_removal;
};

// insert_at, also giving back the host tet's vertices and the point's weights in it (recorded
// before the insertion).
struct LocatedInsertion {
  InsertResult result;
  InsertedVertex inserted;
};
LocatedInsertion insert_located(RemeshMesh& mesh, const Location& where, const Vec3& p);

}  // namespace incise::sim::remesh
