#pragma once
// Corotational FEM (polar) with averaged nodal pressure: linear tets without volumetric locking.
//
// A linear tet has one volume change per element. As nu -> 1/2, keeping every element's volume
// leaves too few motions: the mesh locks, stiffer than the tissue (Lame's thick cylinder at nu
// 0.4999: plain tets 24 % short, this model 5 %; at the liver's nu 0.45 both are within 5 %:
// tests/sim/models/nodal_pressure_fem_test.cpp; the station liver: docs/station_accuracy.md).
// Averaged nodal pressure (Bonet and Burton 1998, "A simple average nodal pressure tetrahedral
// element"; Bonet, Marriott and Hassan 2001) keeps the deviatoric part of the corotational energy
// per element and takes the volumetric part per node, from the volume change averaged over the
// node's elements:
//
//   eps_e = sym(R_e^T F_e) - I,  theta_e = tr(eps_e),  kappa_e = lambda_e + 2 mu_e / 3
//   W_n = sum_{e at n} V_e / 4,  theta_n = sum_{e at n} (V_e / 4) theta_e / W_n,
//   K_n = sum_{e at n} (V_e / 4) kappa_e / W_n
//   E = sum_e V_e mu_e dev(eps_e):dev(eps_e) + sum_n W_n K_n theta_n^2 / 2.
//
// With R_e the polar rotation, d theta_e = tr(R_e^T dF_e) (R_e maximises tr(R^T F), so its own
// change drops out), and the forces are E's exact gradient: each element carries the stress
//   sigma_e = 2 mu_e dev(eps_e) + pbar_e I,   pbar_e = (1/4) sum_{n of e} K_n theta_n,
// which is the plain corotational stress plus (pbar_e - kappa_e theta_e) I. So this model is
// CorotationalFem (its vectorised kernel, its damping) plus that correction, a second pass over
// the elements with the rotations the kernel just found. Each element's correction is a stress
// R_e (c I): no net force, no net torque (R_e F_e^T is symmetric for the polar R), zero under
// any uniform deformation (theta_n = theta_e everywhere).
//
// Stiffness (the corotational K of the last prepare_stiffness, R held fixed) plus
//   sum_n (K_n / W_n) G_n G_n^T - sum_e kappa_e V_e g_e g_e^T,
//   g_e = d theta_e / dx (node a's block R_e grad N_a),  G_n = sum_{e at n} (V_e / 4) g_e,
// which couples a node's neighbours' neighbours: the block assembly goes through the triplets
// (Model's default).
//
// A softened sliver (soften_element: too thin for the explicit step) keeps its own, softened,
// volumetric term and stays out of the nodal averages: averaged with stiff neighbours it would
// get their stiffness back.
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "sim/models/corotational_fem.h"

namespace incise::sim {

class NodalPressureFem final : public CorotationalFem {
 public:
  // As CorotationalFem with polar rotations. Throws std::invalid_argument as it does.
  NodalPressureFem(const TetMesh& mesh, std::vector<ElementMaterial> materials);
  // "corotational_nodal_pressure", the scene name.
  std::string_view name() const override;
  std::unique_ptr<Model> clone() const override {
    return std::make_unique<NodalPressureFem>(*this);
  }

  void add_forces(const Points& x, const Points& v, Points& f) override;
  void prepare_stiffness(const Points& x) override;
  void add_stiffness_times(const Points& dx, Points& out) const override;
  void add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const override;
  void system_blocks(std::vector<std::pair<int, int>>& blocks) const override;
  void add_system_blocks(Real damping_scale, Real stiffness_scale,
                         const BlockTarget& target) const override;
  Real potential_energy(const Points& x) const override;
  void update_topology(const TetMesh& mesh) override;
  void update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                       std::span<const int> changed) override;
  bool soften_element(int t, Real factor) override;

 private:
  // Whether slot t takes part in the nodal averages (alive, not softened).
  bool averaged(int t) const;
  // W_n and K_n from the elements (after any change of elements or softening).
  void refresh_nodes();
  // out += sign times the correction's forces at u: theta_e = tr(R_e^T Ds_e(u) Dm_e^-1) - offset
  // (rotations[t]: R_e) for the averaged elements, their nodal pressures K_n theta_n, and each
  // element's stress (pbar_e - kappa_e theta_e) R_e. With u = x, offset 3 and sign 1 these are
  // the forces; with u = dx, offset 0 and sign -1, K dx.
  void add_correction(const Points& u, std::span<const Mat3> rotations, Real offset, Real sign,
                      Points& out) const;

  std::vector<char> softened_;        // #slots
  VecX node_weight_;                  // #nodes W_n [m^3]
  VecX node_kappa_;                   // #nodes K_n [Pa]
  std::vector<Mat3> rotation_;        // #slots: R_e of the last add_forces
  std::vector<Mat3> stiff_rotation_;  // #slots: R_e of the last prepare_stiffness
  mutable std::vector<Real> theta_;   // #slots scratch: theta_e
  mutable VecX pressure_;             // #nodes scratch: K_n theta_n [Pa]
};

}  // namespace incise::sim
