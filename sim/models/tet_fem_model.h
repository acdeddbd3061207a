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
//
// With A = F the viscous stiffness grows as |F|^2: a stretched sliver (F in the tens, after a cut)
// becomes far stiffer in damping than the explicit step allows, and its growth feeds itself (a
// blow-up within a few steps). So beta is scaled by viscous_scale(A) = min(1, 3 / |A|_F^2): never
// more viscous stiffness than at rest (|I|_F^2 = 3), the value the stable step assumes. A scalar
// keeps the stress torque-free and dissipative; elements stretched less than that are unchanged.
#include <cmath>
#include <concepts>
#include <cstdint>
#include <stdexcept>
#include <string>
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

// The factor on beta for a damping frame A (see the header): min(1, 3 / |A|_F^2).
inline Real viscous_scale(const Mat3& frame) {
  const Real norm2 = frame.squaredNorm();
  return norm2 > 3 ? 3 / norm2 : Real(1);
}

// The 3x3 block (b, a) of the element matrix of the linear elastic stress in a frame A,
// dP = A C(sym(A^T dF)), for nodes with shape-function gradients g_a, g_b: the force on node b
// from a unit move u of node a is
//   K_ba u = V0 [mu (g_a . g_b) A A^T + mu h_a h_b^T + lambda h_b h_a^T] u,   h = A g
// (dF = u g_a^T, then C(sym(A^T dF)) g_b expanded). A = R gives the corotational stiffness
// R K_rest R^T, A = I the linear one, A = F the Kelvin-Voigt damping of the rotation-invariant
// models.
inline Mat3 frame_block(const Vec3& g_a, const Vec3& g_b, const Vec3& h_a, const Vec3& h_b,
                        const Mat3& frame_gram, const Lame& lame, Real volume) {
  return volume * (lame.mu * g_a.dot(g_b) * frame_gram + lame.mu * h_a * h_b.transpose() +
                   lame.lambda * h_b * h_a.transpose());
}

// The kernels whose stress differential is the linear one in a frame (stiffness_frame(state)):
// their element stiffness comes from frame_block, 5-10x cheaper than column by column.
template <class Kernel>
concept FrameLinearKernel = requires(const Kernel& k, const typename Kernel::State& s) {
  { k.stiffness_frame(s) } -> std::convertible_to<Mat3>;
};

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
      if (!elements_.alive(t)) continue;
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
        s.first_piola +=
            beta * viscous_scale(a) * a * linear_stress(sym(a.transpose() * rate), lame);
      }
      scatter_stress(elements_, t, s.first_piola, f);
    }
    health_ = health;
  }

  void prepare_stiffness(const Points& x) override {
    for (int t = 0; t < elements_.num_tets(); ++t) {
      if (!elements_.alive(t)) continue;
      const Mat3 deformation =
          edge_matrix(x, elements_.tets, t) * elements_.rest_inverse[static_cast<std::size_t>(t)];
      states_[static_cast<std::size_t>(t)] =
          kernel_.linearize(deformation, elements_.lame[static_cast<std::size_t>(t)]);
    }
  }

  void add_stiffness_times(const Points& dx, Points& out) const override {
    for (int t = 0; t < elements_.num_tets(); ++t) {
      if (!elements_.alive(t)) continue;
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
      if (!elements_.alive(t)) continue;
      const Real beta = elements_.damping(t);
      if (!(beta > 0)) continue;
      const std::size_t ts = static_cast<std::size_t>(t);
      const Mat3 rate = edge_matrix(dv, elements_.tets, t) * elements_.rest_inverse[ts];
      const Mat3 a = kernel_.damping_frame(states_[ts]);
      scatter_stress(elements_, t,
                     -beta * viscous_scale(a) * a *
                         linear_stress(sym(a.transpose() * rate), elements_.lame[ts]),
                     out);
    }
  }

  void add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const override {
    for (int t = 0; t < elements_.num_tets(); ++t) {
      if (!elements_.alive(t)) continue;
      const std::size_t ts = static_cast<std::size_t>(t);
      const Gradients g = gradients(t);
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

  void add_damping_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const override {
    for (int t = 0; t < elements_.num_tets(); ++t) {
      if (!elements_.alive(t)) continue;
      const std::size_t ts = static_cast<std::size_t>(t);
      const Mat3 frame = kernel_.damping_frame(states_[ts]);
      const Real beta = elements_.damping(t) * viscous_scale(frame);
      const Mat3 gram = frame * frame.transpose();
      const Gradients g = gradients(t);
      const Gradients h = frame * g;
      for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) {
          const Mat3 block = beta * frame_block(g.col(a), g.col(b), h.col(a), h.col(b), gram,
                                                elements_.lame[ts], elements_.rest_volume(t));
          for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) {
              triplets.emplace_back(3 * elements_.tets(t, b) + r, 3 * elements_.tets(t, a) + c,
                                    block(r, c));
            }
          }
        }
      }
    }
  }

  // 10 blocks per tet, (b, a) for b >= a (Model: the off-diagonal ones are mirrored).
  void system_blocks(std::vector<std::pair<int, int>>& blocks) const override {
    for (int t = 0; t < elements_.num_tets(); ++t) {
      if (!elements_.alive(t)) continue;
      for (int a = 0; a < 4; ++a) {
        for (int b = a; b < 4; ++b)
          blocks.emplace_back(elements_.tets(t, b), elements_.tets(t, a));
      }
    }
  }

  void add_system_blocks(Real damping_scale, Real stiffness_scale,
                         const BlockTarget& target) const override {
    std::size_t k = 0;  // the block of system_blocks' order
    for (int t = 0; t < elements_.num_tets(); ++t) {
      if (!elements_.alive(t)) continue;
      const std::size_t ts = static_cast<std::size_t>(t);
      const Lame& lame = elements_.lame[ts];
      const Real volume = elements_.rest_volume(t);
      const Gradients g = gradients(t);
      const Mat3 damping_frame = kernel_.damping_frame(states_[ts]);
      const Real beta = damping_scale * elements_.damping(t) * viscous_scale(damping_frame);
      const Mat3 damping_gram = damping_frame * damping_frame.transpose();
      const Gradients hd = damping_frame * g;
      if constexpr (FrameLinearKernel<Kernel>) {
        // frame_block for the stiffness (frame A, scale c) and the damping (frame A_d, scale b
        // beta) summed with the scalars folded in once per tet:
        //   block = (g_a . g_b) S + h_a p_b^T + q_b h_a^T + hd_a pd_b^T + qd_b hd_a^T.
        const Mat3 frame = kernel_.stiffness_frame(states_[ts]);
        const Gradients h = frame * g;
        const Real k_scale = stiffness_scale * volume;
        const Real d_scale = beta * volume;
        const Mat3 gram =
            (k_scale * lame.mu) * (frame * frame.transpose()) + (d_scale * lame.mu) * damping_gram;
        const Gradients p = (k_scale * lame.mu) * h;
        const Gradients q = (k_scale * lame.lambda) * h;
        const Gradients pd = (d_scale * lame.mu) * hd;
        const Gradients qd = (d_scale * lame.lambda) * hd;
        for (int a = 0; a < 4; ++a) {
          for (int b = a; b < 4; ++b) {
            Mat3 block = g.col(a).dot(g.col(b)) * gram;
            block.noalias() += h.col(a) * p.col(b).transpose();
            block.noalias() += q.col(b) * h.col(a).transpose();
            if (beta > 0) {
              block.noalias() += hd.col(a) * pd.col(b).transpose();
              block.noalias() += qd.col(b) * hd.col(a).transpose();
            }
            target.add(k++, block);
          }
        }
      } else {
        // Column (a, c) of the element K: a unit move of node a along c, dF = e_c g_a^T.
        for (int a = 0; a < 4; ++a) {
          Mat3 columns[4];
          for (int c = 0; c < 3; ++c) {
            Mat3 d_deformation = Mat3::Zero();
            d_deformation.row(c) = g.col(a).transpose();
            const Mat3 dp = kernel_.stress_differential(states_[ts], d_deformation, lame);
            for (int b = a; b < 4; ++b)
              columns[b].col(c) = (stiffness_scale * volume) * dp * g.col(b);
          }
          for (int b = a; b < 4; ++b) {
            if (beta > 0) {
              columns[b] += beta * frame_block(g.col(a), g.col(b), hd.col(a), hd.col(b),
                                               damping_gram, lame, volume);
            }
            target.add(k++, columns[b]);
          }
        }
      }
    }
  }

  Real potential_energy(const Points& x) const override {
    Real energy = 0;
    for (int t = 0; t < elements_.num_tets(); ++t) {
      if (!elements_.alive(t)) continue;
      const std::size_t ts = static_cast<std::size_t>(t);
      const Mat3 deformation = edge_matrix(x, elements_.tets, t) * elements_.rest_inverse[ts];
      energy += elements_.rest_volume(t) * kernel_.energy_density(deformation, elements_.lame[ts]);
    }
    return energy;
  }

  void update_topology(const TetMesh& mesh) override {
    rebuild(mesh);
    topology_changed();
  }

  // Local: only the changed slots' element data, linearisation and nodes' masses (model.h).
  void update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                       std::span<const int> changed) override {
    update_tet_elements(elements_, mesh, alive, changed, materials_);
    states_.resize(static_cast<std::size_t>(elements_.num_tets()),
                   kernel_.linearize(Mat3::Identity(), Lame{}));
    material_lame_.resize(elements_.lame.size());
    for (const int t : changed)
      material_lame_[static_cast<std::size_t>(t)] = elements_.lame[static_cast<std::size_t>(t)];
    for (const int t : changed) {
      if (!elements_.alive(t)) continue;
      const std::size_t ts = static_cast<std::size_t>(t);
      states_[ts] =
          kernel_.linearize(edge_matrix(mesh.rest, elements_.tets, t) * elements_.rest_inverse[ts],
                            elements_.lame[ts]);
    }
    topology_changed();
  }

  ModelHealth health() const override { return health_; }

  bool soften_element(int t, Real factor) override {
    if (t < 0 || t >= elements_.num_tets() || !(factor > 0 && factor <= 1)) {
      throw std::invalid_argument("soften_element: slot " + std::to_string(t) + " or factor " +
                                  std::to_string(factor) + " out of range");
    }
    const std::size_t ts = static_cast<std::size_t>(t);
    elements_.lame[ts].mu = factor * material_lame_[ts].mu;
    elements_.lame[ts].lambda = factor * material_lame_[ts].lambda;
    return true;
  }

 protected:
  const Kernel& kernel() const { return kernel_; }

 private:
  using Gradients = Eigen::Matrix<Real, 3, 4>;

  // Shape-function gradients g_a of tet t (columns): g_k is row k - 1 of Dm^-1, g_0 = -(g_1 + g_2
  // + g_3).
  Gradients gradients(int t) const {
    Gradients g;
    g.rightCols<3>() = elements_.rest_inverse[static_cast<std::size_t>(t)].transpose();
    g.col(0) = -g.rightCols<3>().rowwise().sum();
    return g;
  }

  // Element data from the mesh's rest state; the linearisation starts at rest.
  void rebuild(const TetMesh& mesh) {
    elements_ = make_tet_elements(mesh, materials_);
    material_lame_ = elements_.lame;
    states_.assign(static_cast<std::size_t>(elements_.num_tets()),
                   kernel_.linearize(Mat3::Identity(), Lame{}));
    prepare_stiffness(mesh.rest);
    health_ = {};
  }

  std::vector<ElementMaterial> materials_;
  Kernel kernel_;
  TetElements elements_;
  std::vector<Lame> material_lame_;  // #slots: the materials' values, before soften_element
  std::vector<typename Kernel::State> states_;
  ModelHealth health_;
};

}  // namespace incise::sim
