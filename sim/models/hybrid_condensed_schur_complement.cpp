// The hybrid condensed model's static condensation of its far field: K* and D* as Schur
// complements over the interior nodes (Guyan reduction for the damping), and the far field's mass
// lumped onto the retained nodes.
#include <algorithm>
#include <stdexcept>

#include "sim/models/hybrid_condensed_model.h"

#include <memory>
#include "sim/models/hybrid_condensed_partition.h"
#include "sim/models/linear_fem.h"

namespace incise::sim {
namespace {

// Columns of K* computed per batch of solves: bounds the dense Kii^-1 Kis work array to
// 3 #interior x kBatch doubles.
constexpr Eigen::Index kBatch = 64;

}  // namespace

void HybridCondensedModel::condense_far_field(const TetMesh& far,
                                              const std::vector<ElementMaterial>& materials,
                                              const std::vector<int>& local, Eigen::Index s_dofs,
                                              Eigen::Index i_dofs) {
  // The far field's K, D (= beta K per tet) and lumped masses from the linear FEM.
  far_masses_ = VecX::Zero(far.num_nodes());
  k_star_.resize(0, 0);
  d_star_.resize(0, 0);
  if (far.num_tets() > 0) {
    const LinearFem linear(far, materials);
    Triplets k_entries, d_entries;
    linear.add_stiffness_triplets(k_entries);
    linear.add_damping_triplets(d_entries);
    const VecX& beta = linear.elements().damping;
    // One viscosity over the far field (the usual case): D* = beta K*, one dense matrix fewer
    // and one matrix-vector product per force evaluation instead of two.
    const bool uniform = (beta.array() == beta(0)).all();
    if (uniform) far_beta_ = beta(0);
    const bool damped = !uniform && (beta.array() > 0).any();
    const Partition k = partition(k_entries, local, s_dofs, i_dofs);
    const Partition d = damped ? partition(d_entries, local, s_dofs, i_dofs) : Partition{};
    k_star_ = k.ss;
    if (damped) d_star_ = d.ss;
    if (i_dofs > 0) {
      // Fixed once made (the far field never changes): clones share it.
      auto solver = std::make_shared<Eigen::SimplicialLDLT<Eigen::SparseMatrix<Real>>>(k.ii);
      interior_solver_ = solver;
      if (solver->info() != Eigen::Success || !(solver->vectorD().minCoeff() > 0)) {
        throw std::invalid_argument(
            where("the far field's interior stiffness Kii is not positive definite (degenerate "
                  "far-field tets?)"));
      }
      k_is_ = k.is;
      // Per batch b of columns: X_b = Kii^-1 Kis_b (= -T_b), K*_b = Kss_b - Ksi X_b and, with
      // T^T y = -Ksi Kii^-1 y, D*_b = Dss_b - Dsi X_b - Ksi Kii^-1 (Dis_b - Dii X_b).
      for (Eigen::Index b = 0; b < s_dofs; b += kBatch) {
        const Eigen::Index w = std::min(kBatch, s_dofs - b);
        const Eigen::MatrixXd x_b = solver->solve(Eigen::MatrixXd(k.is.middleCols(b, w)));
        k_star_.middleCols(b, w).noalias() -= k.si * x_b;
        if (damped) {
          const Eigen::MatrixXd y_b = Eigen::MatrixXd(d.is.middleCols(b, w)) - d.ii * x_b;
          d_star_.middleCols(b, w).noalias() -= d.si * x_b;
          d_star_.middleCols(b, w).noalias() -= k.si * solver->solve(y_b);
        }
      }
    }
    // Lump the far field's mass onto its retained nodes, scaled to keep its total.
    const VecX& lumped = linear.masses();
    Real retained_share = 0;
    for (const int i : retained_)
      retained_share += lumped(i);
    const Real scale = lumped.sum() / retained_share;
    for (const int i : retained_)
      far_masses_(i) = scale * lumped(i);
  }
}

}  // namespace incise::sim
