#pragma once
// Per-tet data every tetrahedral model shares: rest volumes, shape-function gradients, per-tet
// material constants from tissue labels, lumped masses. Structure of arrays, one entry per tet.
//
// Linear tet kinematics: with the rest edge matrix Dm = [X1 - X0, X2 - X0, X3 - X0] and the current
// one Ds = [x1 - x0, x2 - x0, x3 - x0], the deformation gradient is F = Ds Dm^-1, constant over
// the tet. For a first Piola-Kirchhoff stress P(F) the nodal forces are
//   [f1 f2 f3] = -V0 P Dm^-T,  f0 = -(f1 + f2 + f3)
// (the gradient of V0 Psi(F) with respect to the node positions).
#include <Eigen/Sparse>
#include <span>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/models/model.h"

namespace incise::sim {

// Lame parameters of an isotropic material.
struct Lame {
  Real mu = 0;      // shear modulus [Pa]
  Real lambda = 0;  // first Lame parameter [Pa]
};

// mu = E / (2 (1 + nu)),  lambda = E nu / ((1 + nu) (1 - 2 nu)).
Lame lame_from_youngs(Real youngs_modulus, Real poisson_ratio);

struct TetElements {
  Tets tets;                       // #tets by 4 node indices
  VecX rest_volume;                // #tets V0 [m^3], > 0
  std::vector<Mat3> rest_inverse;  // #tets Dm^-1 [1/m]; its rows are the gradients of N1..N3
  std::vector<Lame> lame;          // #tets
  VecX youngs_modulus;             // #tets E [Pa]
  VecX damping;                    // #tets ElementMaterial::damping
  VecX density;                    // #tets [kg/m^3]
  VecX masses;                     // #nodes lumped masses [kg]: density V0 / 4 from each tet
  // #tets: 1 where the slot holds an element. After local updates (update_tet_elements) slots
  // may be empty; every element loop skips them.
  std::vector<char> alive_slots;
  std::vector<int> node_elements;  // #nodes: how many elements each node belongs to

  int num_tets() const { return static_cast<int>(tets.rows()); }  // slots, alive or not
  bool alive(int t) const { return alive_slots[static_cast<std::size_t>(t)] != 0; }
  int num_nodes() const { return static_cast<int>(masses.size()); }
};

// Builds the element data of mesh (its rest configuration, tets and labels).
//   materials  material of label l at materials[l]
// Throws std::invalid_argument, naming the tet or label, for a label without a material, a
// material constant out of range (E > 0, -1 < nu < 0.5, density > 0, damping >= 0) or a tet with
// non-positive rest volume.
TetElements make_tet_elements(const TetMesh& mesh, const std::vector<ElementMaterial>& materials);

// Local update after a topology change (remeshing, cutting): mesh.tets row s is slot s, holding an
// element where alive[s] != 0 (other rows are ignored). Only the slots in `changed` are
// recomputed: an element leaving a slot takes its mass off its nodes, one arriving adds its own.
// The arrays grow to mesh's slot and node counts (new nodes start without mass). A node whose
// last element left gets exactly zero mass. Throws std::invalid_argument as make_tet_elements
// for a new element (bad label or node, non-positive rest volume), checked before anything
// changes.
void update_tet_elements(TetElements& elements, const TetMesh& mesh, const std::vector<char>& alive,
                         std::span<const int> changed,
                         const std::vector<ElementMaterial>& materials);

// The consistent mass matrix M_ij = density V0 (1 + delta_ij) / 20 of each tet's linear shape
// functions, per coordinate, appended as (row, column, value) over the 3 #nodes degrees of
// freedom (node i's x, y, z are 3i, 3i+1, 3i+2); duplicates add up. Its row sums are the lumped
// masses.
void add_consistent_mass_triplets(const TetElements& elements,
                                  std::vector<Eigen::Triplet<Real>>& triplets);

// Ds of tet t at positions x (#nodes by 3 [m]): columns x1 - x0, x2 - x0, x3 - x0.
inline Mat3 edge_matrix(const Points& x, const Tets& tets, int t) {
  const Vec3 x0 = row3(x, tets(t, 0));
  Mat3 ds;
  for (int k = 0; k < 3; ++k)
    ds.col(k) = row3(x, tets(t, k + 1)) - x0;
  return ds;
}

// Adds the nodal forces of the first Piola stress p on tet t to f: [f1 f2 f3] = -V0 p Dm^-T.
inline void scatter_stress(const TetElements& elements, int t, const Mat3& p, Points& f) {
  const Mat3 h = -elements.rest_volume(t) * p * elements.rest_inverse[t].transpose();
  const Vec3 h0 = -(h.col(0) + h.col(1) + h.col(2));
  f.row(elements.tets(t, 0)) += h0.transpose();
  for (int k = 0; k < 3; ++k)
    f.row(elements.tets(t, k + 1)) += h.col(k).transpose();
}

}  // namespace incise::sim
