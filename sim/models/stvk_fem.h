#pragma once

#include <string_view>
#include <vector>

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
struct StVenantKirchhoffKernel {
  struct State {
    Mat3 deformation = Mat3::Identity();  // F
    Mat3 second_piola = Mat3::Zero();     // S
  };
  Real energy_density(const Mat3& deformation, const Lame& lame) const {
    const Mat3 green = (deformation.transpose() * deformation - Mat3::Identity()) / 2;
    return lame.mu * green.squaredNorm() + lame.lambda / 2 * green.trace() * green.trace();
  }
  ElementStress stress(const Mat3& deformation, const Lame& lame) const {
    const Mat3 green = (deformation.transpose() * deformation - Mat3::Identity()) / 2;
    return {deformation * linear_stress(green, lame), deformation, false};
  }
  State linearize(const Mat3& deformation, const Lame& lame) const {
    const Mat3 green = (deformation.transpose() * deformation - Mat3::Identity()) / 2;
    return {deformation, linear_stress(green, lame)};
  }
  Mat3 stress_differential(const State& s, const Mat3& d_deformation, const Lame& lame) const {
    return d_deformation * s.second_piola +
           s.deformation * linear_stress(sym(s.deformation.transpose() * d_deformation), lame);
  }
  Mat3 damping_frame(const State& s) const { return s.deformation; }
};

class StVenantKirchhoffFem final : public TetFemModel<StVenantKirchhoffKernel> {
 public:
  //   mesh       rest positions, tets (positively oriented) and labels
  //   materials  material of tet label l at materials[l]; damping is beta [s] (tet_fem_model.h)
  // Throws std::invalid_argument as make_tet_elements.
  StVenantKirchhoffFem(const TetMesh& mesh, std::vector<ElementMaterial> materials);
  std::string_view name() const override { return "stvk"; }
};

extern template class TetFemModel<StVenantKirchhoffKernel>;

}  // namespace incise::sim
