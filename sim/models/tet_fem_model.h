#pragma once
// The element loops shared by the tetrahedral FEM models (linear, corotational, St
// Venant-Kirchhoff, Neo-Hookean). A model is this loop over a material kernel, a small struct of
// pure functions of the deformation gradient F of one tet (the kernel is a template parameter, so
// nothing is virtual per element):
//
//   struct Kernel {
//     struct State;                                        // per-tet linearisation
//     Real energy_density(const Mat3& F, const Lame&) const;          // Psi(F) [J/m^3]
//     ElementStress stress(const Mat3& F, const Lame&) const;         // P = dPsi/dF and more
//     State linearize(const Mat3& F, const Lame&) const;
//     Mat3 stress_differential(const State&, const Mat3& dF, const Lame&) const;  // dP
//     Mat3 damping_frame(const State&) const;
//   };
//
// Damping (every FEM model): Kelvin-Voigt viscosity, a viscous first Piola stress
//   P_v = beta A C(sym(A^T dF/dt)),   C(e) = 2 mu e + lambda tr(e) I,   beta =
//   ElementMaterial::damping [s]
// with the kernel's damping frame A: I for linear FEM (so D = beta K_rest, Rayleigh stiffness-
// proportional damping) and F for the rotation-invariant models (corotational, St Venant-Kirchhoff,
// Neo-Hookean: the viscous stress beta C(rate of Green strain), equal to beta K_rest at rest). A
// rigid motion is thus never damped in the rotation-invariant models, the viscous forces have no
// net torque (P_v F^T = F S_v F^T is symmetric), and D is symmetric positive semi-definite.
// add_forces uses the frame at x; add_damping_times uses the frame of the last prepare_stiffness.
#include <cmath>
#include <vector>

#include "sim/models/model.h"
#include "sim/models/tet_elements.h"

namespace incise::sim {

// What a kernel returns for one tet at F.
struct ElementStress {
  Mat3 first_piola = Mat3::Zero();  // P [Pa]
  Mat3 damping_frame = Mat3::Identity();
  bool degenerate = false;  // the kernel had to fall back (e.g. no rotation from a flat tet)
};

// C(e) = 2 mu e + lambda tr(e) I for a symmetric e.
inline Mat3 linear_stress(const Mat3& e, const Lame& lame) {
  return 2 * lame.mu * e + lame.lambda * e.trace() * Mat3::Identity();
}

inline Mat3 sym(const Mat3& a) {
  return Real(0.5) * (a + a.transpose());
}

// |det F| below this counts as a degenerate element in ModelHealth (a millionth of the rest
// volume).
inline constexpr Real kDegenerateVolumeRatio = 1e-6;

template <class Kernel>
class TetFemModel : public Model {
 public:
  TetFemModel(const TetMesh& mesh, std::vector<ElementMaterial> materials, Kernel kernel)
      : materials_(std::move(materials)), kernel_(std::move(kernel)) {
    rebuild(mesh);
  }

  const VecX& masses() const override { return elements_.masses; }
  const TetElements& elements() const { return elements_; }

  void add_forces(const Points& x, const Points& v, Points& f) override {
    ModelHealth health;
    for (int t = 0; t < elements_.num_tets(); ++t) {
      const Mat3& dm_inv = elements_.rest_inverse[static_cast<std::size_t>(t)];
      const Lame& lame = elements_.lame[static_cast<std::size_t>(t)];
      const Mat3 deformation = edge_matrix(x, elements_.tets, t) * dm_inv;
      const Real j = deformation.determinant();
      health.inverted_elements += j <= 0 ? 1 : 0;
      ElementStress s = kernel_.stress(deformation, lame);
      health.degenerate_elements +=
          (s.degenerate || !(std::abs(j) >= kDegenerateVolumeRatio)) ? 1 : 0;
      const Real beta = elements_.damping(t);
      if (beta > 0) {
        const Mat3 rate = edge_matrix(v, elements_.tets, t) * dm_inv;
        const Mat3& a = s.damping_frame;
        s.first_piola += beta * a * linear_stress(sym(a.transpose() * rate), lame);
      }
      scatter_stress(elements_, t, s.first_piola, f);
    }
    health_ = health;
  }

  void prepare_stiffness(const Points& x) override {
    for (int t = 0; t < elements_.num_tets(); ++t) {
      const Mat3 deformation =
          edge_matrix(x, elements_.tets, t) * elements_.rest_inverse[static_cast<std::size_t>(t)];
      states_[static_cast<std::size_t>(t)] =
          kernel_.linearize(deformation, elements_.lame[static_cast<std::size_t>(t)]);
    }
  }

  void add_stiffness_times(const Points& dx, Points& out) const override {
    for (int t = 0; t < elements_.num_tets(); ++t) {
      const std::size_t ts = static_cast<std::size_t>(t);
      const Mat3 d_deformation = edge_matrix(dx, elements_.tets, t) * elements_.rest_inverse[ts];
      // K = -df/dx, so K dx is the force of -dP.
      scatter_stress(elements_, t,
                     -kernel_.stress_differential(states_[ts], d_deformation, elements_.lame[ts]),
                     out);
    }
  }

  void add_damping_times(const Points& dv, Points& out) const override {
    for (int t = 0; t < elements_.num_tets(); ++t) {
      const Real beta = elements_.damping(t);
      if (!(beta > 0)) continue;
      const std::size_t ts = static_cast<std::size_t>(t);
      const Mat3 rate = edge_matrix(dv, elements_.tets, t) * elements_.rest_inverse[ts];
      const Mat3 a = kernel_.damping_frame(states_[ts]);
      scatter_stress(elements_, t,
                     -beta * a * linear_stress(sym(a.transpose() * rate), elements_.lame[ts]), out);
    }
  }

  void add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const override {
    for (int t = 0; t < elements_.num_tets(); ++t) {
      const std::size_t ts = static_cast<std::size_t>(t);
      // Shape-function gradients g_a (columns): g_k is row k - 1 of Dm^-1, g_0 = -(g_1 + g_2 +
      // g_3).
      Eigen::Matrix<Real, 3, 4> g;
      g.rightCols<3>() = elements_.rest_inverse[ts].transpose();
      g.col(0) = -g.rightCols<3>().rowwise().sum();
      const Real volume = elements_.rest_volume(t);
      // Column (a, c) of the element K: a unit displacement of node a along c, dF = e_c g_a^T.
      for (int a = 0; a < 4; ++a) {
        for (int c = 0; c < 3; ++c) {
          Mat3 d_deformation = Mat3::Zero();
          d_deformation.row(c) = g.col(a).transpose();
          const Mat3 dp =
              kernel_.stress_differential(states_[ts], d_deformation, elements_.lame[ts]);
          const int column = 3 * elements_.tets(t, a) + c;
          for (int b = 0; b < 4; ++b) {
            const Vec3 block = volume * dp * g.col(b);
            for (int r = 0; r < 3; ++r)
              triplets.emplace_back(3 * elements_.tets(t, b) + r, column, block(r));
          }
        }
      }
    }
  }

  Real potential_energy(const Points& x) const override {
    Real energy = 0;
    for (int t = 0; t < elements_.num_tets(); ++t) {
      const std::size_t ts = static_cast<std::size_t>(t);
      const Mat3 deformation = edge_matrix(x, elements_.tets, t) * elements_.rest_inverse[ts];
      energy += elements_.rest_volume(t) * kernel_.energy_density(deformation, elements_.lame[ts]);
    }
    return energy;
  }

  void update_topology(const TetMesh& mesh) override { rebuild(mesh); }

  ModelHealth health() const override { return health_; }

 protected:
  const Kernel& kernel() const { return kernel_; }

 private:
  // Element data from the mesh's rest state; the linearisation starts at rest.
  void rebuild(const TetMesh& mesh) {
    elements_ = make_tet_elements(mesh, materials_);
    states_.assign(static_cast<std::size_t>(elements_.num_tets()),
                   kernel_.linearize(Mat3::Identity(), Lame{}));
    prepare_stiffness(mesh.rest);
    health_ = {};
  }

  std::vector<ElementMaterial> materials_;
  Kernel kernel_;
  TetElements elements_;
  std::vector<typename Kernel::State> states_;
  ModelHealth health_;
};

}  // namespace incise::sim
