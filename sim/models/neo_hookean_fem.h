#pragma once
#include <memory>

#include <string_view>
#include <vector>

#include "sim/models/cofactor.h"
#include "sim/models/projected_tangent.h"
#include "sim/models/tet_fem_model.h"

namespace incise::sim {

// The compressible Neo-Hookean material of Joshi et al. (Nienhuys' form), their equation 4:
//   S = mu (I - C^-1) + lambda J (J - 1) C^-1,   C = F^T F,  J = det F,
// the second Piola stress of the energy density
//   Psi(F) = mu/2 (tr C - 3) - mu ln J + lambda/2 (J - 1)^2
// (S = 2 dPsi/dC, using dJ/dC = J C^-1 / 2). Hence under uniaxial stretch lambda_1 with free
// lateral faces, S22 = 0 gives equation 15 of Joshi et al. for the lateral stretch lambda_2.
// First Piola stress, written with cof F = J F^-T = dJ/dF so that it needs no inverse:
//   P = mu F + (lambda (J - 1) - mu l'(J)) cof F.
// Inversion: ln J has no value for J <= 0. Below J0 (extension_below, default 0.1) ln J is replaced
// by its second-order Taylor expansion at J0,
//   l(J) = ln J0 + (J - J0) / J0 - (J - J0)^2 / (2 J0^2)   for J < J0   (l(J) = ln J otherwise),
// which is C^2 at J0, finite for every J and still increasing for J < 2 J0, so a flat or inverted
// tet has finite energy and a force that raises its volume (restoring). The model is exactly
// that of Joshi et al. for J >= J0. K is the exact Hessian (it can be indefinite far from rest):
//   dP = mu dF + (lambda (J - 1) - mu l'(J)) d(cof F) + (lambda - mu l''(J)) (cof F : dF) cof F,
//   d(cof F) columns: df2 x f3 + f2 x df3,  df3 x f1 + f3 x df1,  df1 x f2 + f1 x df2.
// Projected tangent (Tangent::projected, projected_tangent.h): with F = U diag(s) V^T, w and c the
// factors of the last two terms and g_i = s_j s_k (the diagonal of cof diag(s)), the blocks are
//   stretch: mu I + c g g^T, plus w s_k at (i, j) and (j, i);
//   pair k:  [[mu, -w s_k], [-w s_k, mu]],  eigenvalues mu + w s_k (twist), mu - w s_k (flip).
// w < 0 under compression (w = -mu at rest), so the twist modes turn negative as soon as a tet is
// compressed (s = 0.95 in every direction, nu = 0.3: mu + w s = -0.31 mu), and every block can when
// it is inverted; that is what makes the exact K indefinite.
struct NeoHookeanKernel {
  Real extension_below = 0.1;  // J0
  Tangent tangent = Tangent::exact;

  struct State {
    Mat3 deformation = Mat3::Identity();  // F
    Mat3 cofactor = Mat3::Identity();     // cof F
    Real cofactor_weight = 0;             // lambda (J - 1) - mu l'(J)
    Real cofactor_curvature = 0;          // lambda - mu l''(J)
    bool projected = false;               // stress_differential uses projection, not the above
    ProjectedTangent projection;
  };

  Real energy_density(const Mat3& deformation, const Lame& lame) const;
  ElementStress stress(const Mat3& deformation, const Lame& lame) const;
  State linearize(const Mat3& deformation, const Lame& lame) const;
  Mat3 stress_differential(const State& s, const Mat3& d_deformation, const Lame& lame) const;
  Mat3 damping_frame(const State& s) const { return s.deformation; }
};

class NeoHookeanFem final : public TetFemModel<NeoHookeanKernel> {
 public:
  //   mesh             rest positions, tets (positively oriented) and labels
  //   materials        material of tet label l at materials[l]; damping is beta [s]
  //   extension_below  J0 in (0, 1]: below it ln J is extended quadratically (see above)
  //   tangent          K exact (the Hessian) or its positive semi-definite projection
  // Throws std::invalid_argument as make_tet_elements, or for J0 outside (0, 1].
  NeoHookeanFem(const TetMesh& mesh, std::vector<ElementMaterial> materials,
                Real extension_below = 0.1, Tangent tangent = Tangent::exact);
  std::string_view name() const override { return "neohookean"; }
  std::unique_ptr<Model> clone() const override { return std::make_unique<NeoHookeanFem>(*this); }
};

extern template class TetFemModel<NeoHookeanKernel>;

}  // namespace incise::sim
