#pragma once
#include <memory>

#include <string_view>
#include <vector>

#include "sim/models/corotational_batch.h"
#include "sim/models/rotation_extraction.h"
#include "sim/models/tet_fem_model.h"

namespace incise::sim {

// Corotational linear elasticity (Physically Realistic FEM, section 2.4): each tet's deformation
// gradient F is split into a rotation R and a stretch U = R^T F (symmetric for polar, upper
// triangular for QR; the paper's polar and QR decompositions), and the small-strain energy is
// taken of the stretch:
//   eps = sym(U) - I,   Psi(F) = mu eps:eps + lambda/2 tr(eps)^2.
// Psi does not change when the tet is rotated (R absorbs the rotation), so the forces, as its exact
// gradient, obey Newton's and Euler's laws in every state: this is the "B updated each step" of
// Physically Realistic FEM (section 3.1), here by differentiating through R rather than by a
// current-configuration B.
//   polar:  P = R C(eps). R^T F is symmetric, so the dR/dF term of the gradient vanishes.
//   QR:     P = R (C(eps) - M). dR/dF does not vanish; M is its exact contribution: with
//           A = C(eps) U^T and a, b, c the antisymmetric parts A10 - A01, A20 - A02, A21 - A12,
//           M10 = a / U00, M20 = b / U00 - c U01 / (U00 U11), M21 = c / U11, else 0
//           (from R^T dR being antisymmetric and dU staying upper triangular).
// Stiffness: K_e = R K_rest,e R^T (dP = R C(sym(R^T dF))), recomputed with R at each
// prepare_stiffness. Like Physically Realistic FEM it omits the terms from the change of R with x
// (and M's change); they are proportional to the stress, so K is exact at any rigidly moved rest
// state and its error grows with the strain. This K is symmetric positive semi-definite in every
// state.
// Damping uses the frame F (the rate of Green strain, as St Venant-Kirchhoff and Neo-Hookean), not
// R: the viscous stress R C(sym(R^T dF/dt)) of D = beta R K_rest R^T has a net torque once the tet
// is deformed (R C S R^T is not symmetric), F C(sym(F^T dF/dt)) has none (tet_fem_model.h).
// An inverted tet keeps a proper rotation (QR: r3 = r1 x r2; polar: sign-fixed SVD), so its stretch
// has a negative entry and the energy pushes it back (a restoring force, no NaN).
struct CorotationalKernel {
  RotationExtraction extraction = RotationExtraction::polar;

  struct State {
    Mat3 rotation = Mat3::Identity();
    Mat3 deformation = Mat3::Identity();
  };

  Real energy_density(const Mat3& deformation, const Lame& lame) const;
  ElementStress stress(const Mat3& deformation, const Lame& lame) const;
  State linearize(const Mat3& deformation, const Lame& lame) const;
  Mat3 stress_differential(const State& state, const Mat3& d_deformation, const Lame& lame) const {
    return state.rotation * linear_stress(sym(state.rotation.transpose() * d_deformation), lame);
  }
  Mat3 stiffness_frame(const State& state) const { return state.rotation; }
  Mat3 damping_frame(const State& state) const { return state.deformation; }
};

class CorotationalFem : public TetFemModel<CorotationalKernel> {
 public:
  //   mesh        rest positions, tets (positively oriented) and labels
  //   materials   material of tet label l at materials[l]; damping is beta [s] (tet_fem_model.h)
  //   extraction  how R is taken from F
  // Throws std::invalid_argument as make_tet_elements.
  CorotationalFem(const TetMesh& mesh, std::vector<ElementMaterial> materials,
                  RotationExtraction extraction);
  // "corotational" (QR) or "corotational_polar", the scene names.
  std::string_view name() const override;
  std::unique_ptr<Model> clone() const override { return std::make_unique<CorotationalFem>(*this); }

  // Through the vectorised kernel (corotational_batch.h), its rotations warm-started from the
  // last call.
  void add_forces(const Points& x, const Points& v, Points& f) override;
  // Through CorotationalKernel::stress one tet at a time: the reference add_forces equals to
  // round-off.
  void add_forces_scalar(const Points& x, const Points& v, Points& f);
  ModelHealth health() const override { return health_; }
  void update_topology(const TetMesh& mesh) override;
  void update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                       std::span<const int> changed) override;
  bool soften_element(int t, Real factor) override;

  const CorotationalBatch& batch() const { return batch_; }

 private:
  CorotationalBatch batch_;
  ModelHealth health_;
};

extern template class TetFemModel<CorotationalKernel>;

}  // namespace incise::sim
