#pragma once
#include <memory>
// Small models with exactly known K, for testing the solvers without the FEM models of
// sim/models/ (which are tested on their own).

#include <Eigen/Sparse>
#include <vector>

#include "sim/mesh/tet_mesh.h"
#include "sim/models/model.h"

namespace incise::sim::testing {

using SparseMatrix = Eigen::SparseMatrix<Real>;

// A linear model: f = -K (x - rest) - D v with D = alpha M + beta K (Rayleigh), exact K for any x.
class LinearModel : public Model {
 public:
  //   rest    #nodes by 3 [m];  masses  #nodes [kg];  stiffness  3 #nodes square, symmetric [N/m]
  LinearModel(Points rest, VecX masses, SparseMatrix stiffness, Real alpha = 0, Real beta = 0);

  std::string_view name() const override { return "test_linear"; }
  std::unique_ptr<Model> clone() const override { return std::make_unique<LinearModel>(*this); }
  const VecX& masses() const override { return masses_; }
  void add_forces(const Points& x, const Points& v, Points& f) override;
  void prepare_stiffness(const Points&) override {}
  void add_stiffness_times(const Points& dx, Points& out) const override;
  void add_damping_times(const Points& dv, Points& out) const override;
  void add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const override;
  void add_damping_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const override;
  Real potential_energy(const Points& x) const override;
  void update_topology(const TetMesh&) override {}
  ModelHealth health() const override { return {}; }

  const SparseMatrix& stiffness() const { return stiffness_; }
  const Points& rest() const { return rest_; }

 private:
  Points rest_;
  VecX masses_;
  SparseMatrix stiffness_;
  Real alpha_, beta_;
  Points work_;
};

// One node of mass m on a spring of stiffness k to its rest position in every axis:
// omega = sqrt(k / m).
LinearModel make_oscillator(Real mass, Real stiffness, Real alpha = 0, Real beta = 0);

// Two nodes of mass 1 at (0, 0, 0) and (1, 0, 0), joined in every axis by a spring of the given
// stiffness: K = k [I, -I; -I, I].
LinearModel make_spring_pair(Real stiffness);

// Constant-strain (linear) tet elasticity at the mesh's rest shape, with Lame constants from E
// and nu: K_ab = V (lambda g_a g_b^T + mu g_b g_a^T + mu (g_a . g_b) I) with g the shape function
// gradients; lumped masses density V / 4 per node.
LinearModel make_linear_tet_model(const TetMesh& mesh, Real youngs_modulus, Real poisson_ratio,
                                  Real density, Real alpha = 0, Real beta = 0);

// Springs between node pairs with the tension T(e) = k1 e + k3 e^3 of the extension
// e = |x_j - x_i| - L (geometrically nonlinear and hardening); exact tangent
//   K_pair = T'(e) n n^T + (T / l) (I - n n^T),  n = (x_j - x_i) / l.
// No damping.
class NonlinearSprings : public Model {
 public:
  NonlinearSprings(Points rest, Edges edges, VecX masses, Real k1, Real k3);

  std::string_view name() const override { return "test_nonlinear_springs"; }
  std::unique_ptr<Model> clone() const override {
    return std::make_unique<NonlinearSprings>(*this);
  }
  const VecX& masses() const override { return masses_; }
  void add_forces(const Points& x, const Points& v, Points& f) override;
  void prepare_stiffness(const Points& x) override;
  void add_stiffness_times(const Points& dx, Points& out) const override;
  void add_damping_times(const Points&, Points&) const override {}
  void add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const override;
  void add_damping_triplets(std::vector<Eigen::Triplet<Real>>&) const override {}
  Real potential_energy(const Points& x) const override;
  void update_topology(const TetMesh&) override {}
  ModelHealth health() const override { return {}; }

  // T(e) [N] for extension e [m].
  Real tension(Real e) const { return k1_ * e + k3_ * e * e * e; }

 private:
  Edges edges_;
  VecX rest_lengths_;
  VecX masses_;
  Real k1_, k3_;
  std::vector<Mat3> blocks_;  // per edge K_pair of the last prepare_stiffness
};

// Total energy: kinetic 1/2 v^T M v + the model's potential [J].
Real total_energy(const Model& model, const Points& x, const Points& v);

}  // namespace incise::sim::testing
