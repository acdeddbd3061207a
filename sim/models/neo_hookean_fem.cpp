#include "sim/models/neo_hookean_fem.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace incise::sim {

template class TetFemModel<NeoHookeanKernel>;

namespace {

// l(J), l'(J), l''(J): ln J, extended below j0 by its Taylor polynomial of degree 2.
struct Log {
  Real value;
  Real slope;
  Real curvature;
};

Log extended_log(Real j, Real j0) {
  if (j >= j0) return {std::log(j), 1 / j, -1 / (j * j)};
  const Real d = j - j0;
  return {std::log(j0) + d / j0 - d * d / (2 * j0 * j0), 1 / j0 - d / (j0 * j0), -1 / (j0 * j0)};
}

}  // namespace

Real NeoHookeanKernel::energy_density(const Mat3& deformation, const Lame& lame) const {
  const Real j = deformation.determinant();
  return lame.mu / 2 * (deformation.squaredNorm() - 3) -
         lame.mu * extended_log(j, extension_below).value + lame.lambda / 2 * (j - 1) * (j - 1);
}

ElementStress NeoHookeanKernel::stress(const Mat3& deformation, const Lame& lame) const {
  const Real j = deformation.determinant();
  const Real weight = lame.lambda * (j - 1) - lame.mu * extended_log(j, extension_below).slope;
  return {lame.mu * deformation + weight * cofactor(deformation), deformation, false};
}

NeoHookeanKernel::State NeoHookeanKernel::linearize(const Mat3& deformation,
                                                    const Lame& lame) const {
  const Real j = deformation.determinant();
  const Log l = extended_log(j, extension_below);
  State s;
  s.deformation = deformation;
  s.cofactor = cofactor(deformation);
  s.cofactor_weight = lame.lambda * (j - 1) - lame.mu * l.slope;
  s.cofactor_curvature = lame.lambda - lame.mu * l.curvature;
  if (tangent == Tangent::projected) {
    const SignedSvd svd = signed_svd(deformation);
    const Vec3& sv = svd.s;
    const Vec3 g(sv(1) * sv(2), sv(0) * sv(2), sv(0) * sv(1));  // diagonal of cof diag(s)
    ProjectedTangent& p = s.projection;
    p.u = svd.u;
    p.v = svd.v;
    p.stretch = lame.mu * Mat3::Identity() + s.cofactor_curvature * g * g.transpose();
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, jj = (k + 2) % 3;
      p.stretch(i, jj) += s.cofactor_weight * sv(k);
      p.stretch(jj, i) += s.cofactor_weight * sv(k);
      p.pair_a(k) = lame.mu;
      p.pair_b(k) = -s.cofactor_weight * sv(k);
      p.pair_c(k) = lame.mu;
    }
    p.clamp_to_positive_semidefinite();
    s.projected = true;
  }
  return s;
}

Mat3 NeoHookeanKernel::stress_differential(const State& s, const Mat3& d_deformation,
                                           const Lame& lame) const {
  if (s.projected) return s.projection.apply(d_deformation);
  const Mat3& df = d_deformation;
  return lame.mu * df + s.cofactor_weight * cofactor_differential(s.deformation, df) +
         s.cofactor_curvature * s.cofactor.cwiseProduct(df).sum() * s.cofactor;
}

NeoHookeanFem::NeoHookeanFem(const TetMesh& mesh, std::vector<ElementMaterial> materials,
                             Real extension_below, Tangent tangent)
    : TetFemModel(mesh, std::move(materials), NeoHookeanKernel{extension_below, tangent}) {
  if (!(extension_below > 0 && extension_below <= 1)) {
    throw std::invalid_argument("Neo-Hookean extension_below must be in (0, 1], got " +
                                std::to_string(extension_below));
  }
}

}  // namespace incise::sim
