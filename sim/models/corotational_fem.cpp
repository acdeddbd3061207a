#include "sim/models/corotational_fem.h"

#include <utility>

namespace incise::sim {

template class TetFemModel<CorotationalKernel>;

namespace {

struct Split {
  Mat3 rotation;
  Mat3 stretch;
  bool degenerate;
};

Split split(const Mat3& deformation, RotationExtraction extraction) {
  if (extraction == RotationExtraction::qr) {
    const QrRotation qr = qr_rotation(deformation);
    return {qr.rotation, qr.upper, qr.degenerate};
  }
  const Mat3 rotation = polar_rotation(deformation);
  return {rotation, rotation.transpose() * deformation, false};
}

}  // namespace

Real CorotationalKernel::energy_density(const Mat3& deformation, const Lame& lame) const {
  const Mat3 strain = sym(split(deformation, extraction).stretch) - Mat3::Identity();
  return lame.mu * strain.squaredNorm() + lame.lambda / 2 * strain.trace() * strain.trace();
}

ElementStress CorotationalKernel::stress(const Mat3& deformation, const Lame& lame) const {
  const Split s = split(deformation, extraction);
  const Mat3 sigma = linear_stress(sym(s.stretch) - Mat3::Identity(), lame);
  if (extraction == RotationExtraction::polar || s.degenerate)
    return {s.rotation * sigma, deformation, s.degenerate};
  const Mat3& u = s.stretch;
  const Mat3 a = sigma * u.transpose();
  const Real skew10 = a(1, 0) - a(0, 1);
  const Real skew20 = a(2, 0) - a(0, 2);
  const Real skew21 = a(2, 1) - a(1, 2);
  Mat3 m = Mat3::Zero();
  m(1, 0) = skew10 / u(0, 0);
  m(2, 0) = skew20 / u(0, 0) - skew21 * u(0, 1) / (u(0, 0) * u(1, 1));
  m(2, 1) = skew21 / u(1, 1);
  return {s.rotation * (sigma - m), deformation, false};
}

CorotationalKernel::State CorotationalKernel::linearize(const Mat3& deformation,
                                                        const Lame&) const {
  return {split(deformation, extraction).rotation, deformation};
}

CorotationalFem::CorotationalFem(const TetMesh& mesh, std::vector<ElementMaterial> materials,
                                 RotationExtraction extraction)
    : TetFemModel(mesh, std::move(materials), CorotationalKernel{extraction}) {
  batch_.assign(elements());
}

void CorotationalFem::add_forces(const Points& x, const Points& v, Points& f) {
  health_ = batch_.add_forces(kernel().extraction, x, v, f);
}

void CorotationalFem::add_forces_scalar(const Points& x, const Points& v, Points& f) {
  TetFemModel::add_forces(x, v, f);
  health_ = TetFemModel::health();
}

void CorotationalFem::update_topology(const TetMesh& mesh) {
  TetFemModel::update_topology(mesh);
  batch_.assign(elements());
  health_ = {};
}

void CorotationalFem::update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                                      std::span<const int> changed) {
  TetFemModel::update_elements(mesh, alive, changed);
  batch_.update(elements(), changed);
}

bool CorotationalFem::soften_element(int t, Real factor) {
  if (!TetFemModel::soften_element(t, factor)) return false;
  batch_.update_material(elements(), t);
  return true;
}

std::string_view CorotationalFem::name() const {
  return kernel().extraction == RotationExtraction::qr ? "corotational" : "corotational_polar";
}

}  // namespace incise::sim
