#include "sim/models/stvk_fem.h"

#include <utility>

namespace incise::sim {

template class TetFemModel<StVenantKirchhoffKernel>;

StVenantKirchhoffKernel::State StVenantKirchhoffKernel::linearize(const Mat3& deformation,
                                                                  const Lame& lame) const {
  const Mat3 green = (deformation.transpose() * deformation - Mat3::Identity()) / 2;
  State state;
  state.deformation = deformation;
  state.second_piola = linear_stress(green, lame);
  if (tangent == Tangent::projected) {
    const SignedSvd svd = signed_svd(deformation);
    const Vec3& s = svd.s;
    const Vec3 stress =
        (lame.mu * (s.array().square() - 1) + lame.lambda / 2 * (s.squaredNorm() - 3))
            .matrix();  // S in the SVD frame (diagonal)
    ProjectedTangent& p = state.projection;
    p.u = svd.u;
    p.v = svd.v;
    p.stretch = lame.lambda * s * s.transpose();
    p.stretch.diagonal() += stress + 2 * lame.mu * s.cwiseAbs2();
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      p.pair_a(k) = stress(j) + lame.mu * s(i) * s(i);
      p.pair_b(k) = lame.mu * s(i) * s(j);
      p.pair_c(k) = stress(i) + lame.mu * s(j) * s(j);
    }
    p.clamp_to_positive_semidefinite();
    state.projected = true;
  }
  return state;
}

StVenantKirchhoffFem::StVenantKirchhoffFem(const TetMesh& mesh,
                                           std::vector<ElementMaterial> materials, Tangent tangent)
    : TetFemModel(mesh, std::move(materials), StVenantKirchhoffKernel{tangent}) {}

}  // namespace incise::sim
