#pragma once
#include <memory>

#include <string_view>
#include <vector>

#include "sim/models/projected_tangent.h"
#include "sim/models/tet_fem_model.h"

namespace incise::sim {

// St Venant-Kirchhoff: linear elasticity in the Green strain E = (F^T F - I) / 2,
//   Psi = mu E:E + lambda/2 tr(E)^2,   S = 2 mu E + lambda tr(E) I,   P = F S,
//   dP = dF S + F (2 mu dE + lambda tr(dE) I),   dE = sym(F^T dF)   (K is the exact Hessian).
// Rotation invariant and exact for large rotations. Its known weakness, kept and reported rather
// than hidden: Psi depends on F only through F^T F, so a tet mirrored through a face (F = R diag(1,
// 1, -1)) is another rest state, and under strong compression the stress softens to zero and the
// force can push a tet further inside out. No NaN arises (P is polynomial in F); inverted tets are
// counted in health(). Use the Neo-Hookean or corotational model where tets may invert.
// Projected tangent (Tangent::projected, projected_tangent.h): with F = U diag(s) V^T, S is
// diagonal in that frame, S_i = mu (s_i^2 - 1) + lambda/2 (|s|^2 - 3), and the blocks are
//   stretch: diag(S_i + 2 mu s_i^2) + lambda s s^T;
//   pair k = (i, j):  [[S_j + mu s_i^2, mu s_i s_j], [mu s_i s_j, S_i + mu s_j^2]].
// Under compression S_i < 0: a pair block turns indefinite as soon as a tet is compressed
// (rotating a compressed tet releases energy), and the stretch block once the stress-strain curve
// turns over (uniaxially, with the other s_j = 1, its entry (mu + lambda/2)(3 s_i^2 - 1) is
// negative below s_i = 1/sqrt(3)). That is the indefinite K the projection removes.
struct StVenantKirchhoffKernel {
  Tangent tangent = Tangent::exact;

  struct State {
    Mat3 deformation = Mat3::Identity();  // F
    Mat3 second_piola = Mat3::Zero();     // S
    bool projected = false;               // stress_differential uses projection, not the above
    ProjectedTangent projection;
  };
  Real energy_density(const Mat3& deformation, const Lame& lame) const {
    const Mat3 green = (deformation.transpose() * deformation - Mat3::Identity()) / 2;
    return lame.mu * green.squaredNorm() + lame.lambda / 2 * green.trace() * green.trace();
  }
  ElementStress stress(const Mat3& deformation, const Lame& lame) const {
    const Mat3 green = (deformation.transpose() * deformation - Mat3::Identity()) / 2;
    return {deformation * linear_stress(green, lame), deformation, false};
  }
  State linearize(const Mat3& deformation, const Lame& lame) const;
  Mat3 stress_differential(const State& s, const Mat3& d_deformation, const Lame& lame) const {
    if (s.projected) return s.projection.apply(d_deformation);
    return d_deformation * s.second_piola +
           s.deformation * linear_stress(sym(s.deformation.transpose() * d_deformation), lame);
  }
  Mat3 damping_frame(const State& s) const { return s.deformation; }
};

class StVenantKirchhoffFem final : public TetFemModel<StVenantKirchhoffKernel> {
 public:
  //   mesh       rest positions, tets (positively oriented) and labels
  //   materials  material of tet label l at materials[l]; damping is beta [s] (tet_fem_model.h)
  //   tangent    K exact (the Hessian) or its positive semi-definite projection
  // Throws std::invalid_argument as make_tet_elements.
  StVenantKirchhoffFem(const TetMesh& mesh, std::vector<ElementMaterial> materials,
                       Tangent tangent = Tangent::exact);
  std::string_view name() const override { return "stvk"; }
  std::unique_ptr<Model> clone() const override {
    return std::make_unique<StVenantKirchhoffFem>(*this);
  }
};

extern template class TetFemModel<StVenantKirchhoffKernel>;

}  // namespace incise::sim
