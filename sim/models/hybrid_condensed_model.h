#pragma once
// The hybrid condensed model (Knee Arthroscopy VR, section VI; docs/condensed_model.md): a body
// split into an operational region, where the surgeon works, modelled by any nonlinear,
// topology-changing model (corotational, Neo-Hookean, ...), and a non-operational region ("far
// field") modelled by linear elasticity whose interior nodes are condensed away. The regions share
// the nodes on their interface, and one global node numbering.
//
// Far field: with its linear FEM stiffness K and damping D (tet_fem_model.h: D = beta K per tet)
// partitioned into retained nodes s (its nodes on the body's boundary surface or shared with the
// operational region) and interior nodes i, the interior is assumed in static equilibrium under
// no load of its own, u_i = T u_s with T = -Kii^-1 Kis, which gives (static condensation,
// Knee Arthroscopy VR eqs. 4-5; Guyan reduction for the damping)
//   K* = Kss - Ksi Kii^-1 Kis,   D* = [I; T]^T D [I; T] = Dss + Dsi T + T^T Dis + T^T Dii T,
//   f_s = -K* (x_s - X_s) - D* v_s.
// Exact for the statics of a linear far field (D* = beta K* when beta is uniform); small
// displacement only: a finite rotation of the far field produces forces (linear_fem.h). K* and D*
// are dense, 3 #retained squared each: 9 n_s^2 doubles (n_s = 1000 retained nodes: 72 MB each,
// and a force evaluation is a 3000 x 3000 matrix-vector product). Meant for far fields of up to a
// few thousand surface nodes.
//
// Interior far-field nodes are not simulated: they get mass 0 (every solver holds a massless node,
// free_coordinates.h), no force and no stiffness; their positions are recovered on demand with
// interior_displacements. The far field's mass is lumped onto its retained nodes, each retained
// node's share (density V0 / 4 per tet) scaled by M_far / (sum of those shares), so the total mass
// is exactly the full mesh's (the far field's centre of mass and inertia do change: its interior
// mass moves to its surface). Gravity on the far field thus acts on the retained nodes only, with
// the right total.
//
// The condensed region is fixed: topology changes (update_elements, update_topology) may only touch
// operational tets and add new ones, which become operational.
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include "sim/models/model.h"

namespace incise::sim {

// Builds the operational region's model on a mesh holding only the operational tets (and every
// node of the full mesh, at the same indices), e.g. the constructor of CorotationalFem.
using RegionModelFactory =
    std::function<std::unique_ptr<Model>(const TetMesh&, const std::vector<ElementMaterial>&)>;

class HybridCondensedModel final : public Model {
 public:
  //   mesh                 rest positions, positively oriented tets and labels of the whole body
  //   operational          #tets: nonzero where the tet belongs to the operational region
  //   materials            material of tet label l at materials[l] (both regions)
  //   make_operational     the operational region's model
  // Throws std::invalid_argument for operational of the wrong size, no operational tet, no
  // factory or a factory returning nothing, a bad label or material or a non-positive tet volume
  // (as make_tet_elements), or a far-field interior that cannot be condensed (Kii not positive
  // definite). Costs one sparse LDLT factorisation of Kii and 3 n_s solves with it (6 n_s with
  // mixed far-field damping), n_s the retained node count.
  HybridCondensedModel(const TetMesh& mesh, const std::vector<char>& operational,
                       const std::vector<ElementMaterial>& materials,
                       const RegionModelFactory& make_operational);

  std::string_view name() const override { return "hybrid_condensed"; }
  std::unique_ptr<Model> clone() const override;
  // Operational lumped masses plus the far field's lumped onto its retained nodes; 0 on condensed
  // interior nodes.
  const VecX& masses() const override { return masses_; }

  void add_forces(const Points& x, const Points& v, Points& f) override;
  void prepare_stiffness(const Points& x) override;
  void add_stiffness_times(const Points& dx, Points& out) const override;
  void add_damping_times(const Points& dv, Points& out) const override;
  void add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const override;
  void add_damping_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const override;
  // The far field's dense blocks (every pair of retained nodes, j <= i) first, then the
  // operational model's.
  void system_blocks(std::vector<std::pair<int, int>>& blocks) const override;
  void add_system_blocks(Real damping_scale, Real stiffness_scale,
                         const BlockTarget& target) const override;
  Real potential_energy(const Points& x) const override;

  // mesh must hold every far-field tet (in any row, nodes in any order); its other tets become
  // the operational region. Throws std::invalid_argument, with the model unchanged, if a far-field
  // tet is missing or an operational tet uses a condensed interior node.
  void update_topology(const TetMesh& mesh) override;
  // Slot view (model.h) of the whole body, in the slot numbering of the mesh the model was built
  // or last update_topology'd with (its tet row t is slot t; new slots are operational). Local:
  // only the operational model's update_elements runs. Throws std::invalid_argument, with the model
  // unchanged, if a far-field slot is changed or not alive, or a new tet uses a condensed interior
  // node.
  void update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                       std::span<const int> changed) override;

  ModelHealth health() const override { return operational_->health(); }
  // An operational slot is softened by the operational model; a far-field one is not (its
  // stiffness is condensed into K*): false. Throws std::invalid_argument for t out of range.
  bool soften_element(int t, Real factor) override;

  // Displacements of the condensed interior nodes, u_i = -Kii^-1 Kis (x_s - X_s), written into
  // x's interior rows as X_i + u_i (e.g. for rendering); other rows are untouched.
  //   x  #nodes by 3 positions [m], at least as many rows as the model was built with
  // Allocates (one sparse solve).
  void recover_interior(Points& x) const;

  // Mesh node indices of the far field's retained nodes (the order of K*'s node blocks) and its
  // condensed interior nodes, both ascending.
  const std::vector<int>& retained_nodes() const { return retained_; }
  const std::vector<int>& interior_nodes() const { return interior_; }
  // K* and D*, 3 #retained square: node retained_nodes()[k]'s x, y, z are rows 3k, 3k+1, 3k+2.
  // D* is 0 x 0 when no far-field tet is damped. condensed_damping allocates: when every far-field
  // tet has the same beta the model keeps only K* and the scalar (D* = beta K*).
  const Eigen::MatrixXd& condensed_stiffness() const { return k_star_; }
  Eigen::MatrixXd condensed_damping() const;
  const Model& operational_model() const { return *operational_; }

 private:
  // Member-wise, operational_ left empty: clone() fills it with a deep copy.
  HybridCondensedModel(const HybridCondensedModel& other);

  // Splits the far field's nodes (those of far's tets) into retained_ (on the body's boundary
  // surface or on an operational tet) and interior_ (condensed_), and returns every mesh dof's
  // index in the far field's matrices: retained dofs first, then interior ones, -1 outside the far
  // field (hybrid_condensed_partition.cpp).
  std::vector<int> partition_nodes(const TetMesh& mesh, const TetMesh& far,
                                   const std::vector<char>& operational);
  // The far field's static condensation from its linear FEM (far: its tets, every node of the
  // mesh): k_star_ and d_star_ or far_beta_, the factorisation of Kii with k_is_, and far_masses_
  // (hybrid_condensed_schur_complement.cpp). s_dofs, i_dofs: 3 #retained, 3 #interior.
  void condense_far_field(const TetMesh& far, const std::vector<ElementMaterial>& materials,
                          const std::vector<int>& local, Eigen::Index s_dofs, Eigen::Index i_dofs);
  // masses_ = the operational model's masses + far_masses_.
  void rebuild_masses();
  // out(3k .. 3k+2) = p.row(retained_[k]), minus the rest position if minus_rest.
  void gather(const Points& p, bool minus_rest, VecX& out) const;
  // out.row(retained_[k]) += scale y(3k .. 3k+2).
  void scatter_add(const VecX& y, Real scale, Points& out) const;
  // Throws std::invalid_argument if tet `row` uses a condensed interior node.
  void check_operational_tet(const Tets& tets, int row) const;

  std::unique_ptr<Model> operational_;

  Points rest_;                  // the constructor's rest positions (far-field nodes)
  Tets far_tets_;                // the far field's tets, each row sorted ascending
  std::vector<char> condensed_;  // #nodes (constructor's): 1 for a condensed interior node
  std::vector<int> retained_, interior_;
  Eigen::MatrixXd k_star_;
  Real far_beta_ = 0;       // > 0: every far-field tet has this beta, D* = far_beta_ K*
  Eigen::MatrixXd d_star_;  // D* for mixed far-field betas, else 0 x 0
  VecX far_masses_;         // #nodes (constructor's) far-field masses lumped onto retained nodes
  VecX masses_;

  // The factorisation of Kii and Kis, kept for recover_interior.
  std::shared_ptr<const Eigen::SimplicialLDLT<Eigen::SparseMatrix<Real>>> interior_solver_;
  Eigen::SparseMatrix<Real> k_is_;

  // Slot bookkeeping for update_elements: region of each global slot (1 = operational), the
  // operational model's slot of each global slot (-1 for far) and back.
  std::vector<char> slot_operational_;
  std::vector<int> operational_slot_, global_slot_;
  TetMesh operational_view_;  // the operational model's slot view, reused between updates

  mutable VecX u_s_, y_s_;  // scratch, 3 #retained
};

}  // namespace incise::sim
