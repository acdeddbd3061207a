#pragma once
#include <memory>

#include <string_view>
#include <vector>

#include "sim/models/tet_fem_model.h"

namespace incise::sim {

// Small-strain (geometrically linear) elasticity on linear tets:
//   eps = sym(F) - I,  Psi = mu eps:eps + lambda/2 tr(eps)^2,  P = 2 mu eps + lambda tr(eps) I.
// K is constant (the rest stiffness). Forces are linear in the displacement, so they vanish for a
// translation but not for a finite rotation (the "ghost forces" of Physically Realistic FEM,
// section 2.4), and their torque about the origin vanishes only when taken at the rest positions
// (sum X_i x f_i = 0; at the current positions it is O(|u|^2)).
struct LinearKernel {
  struct State {};
  Real energy_density(const Mat3& deformation, const Lame& lame) const {
    const Mat3 strain = sym(deformation) - Mat3::Identity();
    return lame.mu * strain.squaredNorm() + lame.lambda / 2 * strain.trace() * strain.trace();
  }
  ElementStress stress(const Mat3& deformation, const Lame& lame) const {
    return {linear_stress(sym(deformation) - Mat3::Identity(), lame), Mat3::Identity(), false};
  }
  State linearize(const Mat3&, const Lame&) const { return {}; }
  Mat3 stress_differential(const State&, const Mat3& d_deformation, const Lame& lame) const {
    return linear_stress(sym(d_deformation), lame);
  }
  Mat3 stiffness_frame(const State&) const { return Mat3::Identity(); }
  Mat3 damping_frame(const State&) const { return Mat3::Identity(); }
};

class LinearFem final : public TetFemModel<LinearKernel> {
 public:
  //   mesh       rest positions, tets (positively oriented) and labels
  //   materials  material of tet label l at materials[l]; damping is beta [s] (tet_fem_model.h)
  // Throws std::invalid_argument as make_tet_elements.
  LinearFem(const TetMesh& mesh, std::vector<ElementMaterial> materials);
  std::string_view name() const override { return "linear"; }
  std::unique_ptr<Model> clone() const override { return std::make_unique<LinearFem>(*this); }
};

extern template class TetFemModel<LinearKernel>;

}  // namespace incise::sim
