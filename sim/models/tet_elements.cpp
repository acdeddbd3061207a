#include "sim/models/tet_elements.h"

#include <stdexcept>
#include <string>

namespace incise::sim {

Lame lame_from_youngs(Real youngs_modulus, Real poisson_ratio) {
  const Real e = youngs_modulus;
  const Real nu = poisson_ratio;
  return {e / (2 * (1 + nu)), e * nu / ((1 + nu) * (1 - 2 * nu))};
}

namespace {

void check_material(const ElementMaterial& m, std::size_t label) {
  const std::string where = "material of label " + std::to_string(label) + ": ";
  if (!(m.youngs_modulus > 0))
    throw std::invalid_argument(where + "Young's modulus must be > 0, got " +
                                std::to_string(m.youngs_modulus));
  if (!(m.poisson_ratio > -1 && m.poisson_ratio < 0.5))
    throw std::invalid_argument(where + "Poisson ratio must be in (-1, 0.5), got " +
                                std::to_string(m.poisson_ratio));
  if (!(m.density > 0))
    throw std::invalid_argument(where + "density must be > 0, got " + std::to_string(m.density));
  if (!(m.damping >= 0))
    throw std::invalid_argument(where + "damping must be >= 0, got " + std::to_string(m.damping));
}

}  // namespace

TetElements make_tet_elements(const TetMesh& mesh, const std::vector<ElementMaterial>& materials) {
  for (std::size_t l = 0; l < materials.size(); ++l)
    check_material(materials[l], l);
  const int num_tets = mesh.num_tets();
  if (mesh.labels.size() != 0 && mesh.labels.size() != num_tets) {
    throw std::invalid_argument("mesh has " + std::to_string(mesh.labels.size()) + " labels for " +
                                std::to_string(num_tets) + " tets");
  }

  TetElements e;
  e.tets = mesh.tets;
  e.rest_volume.resize(num_tets);
  e.rest_inverse.resize(num_tets);
  e.lame.resize(num_tets);
  e.youngs_modulus.resize(num_tets);
  e.damping.resize(num_tets);
  e.density.resize(num_tets);
  e.masses = VecX::Zero(mesh.num_nodes());
  for (int t = 0; t < num_tets; ++t) {
    const int label = mesh.labels.size() == 0 ? 0 : mesh.labels(t);
    if (label < 0 || label >= static_cast<int>(materials.size())) {
      throw std::invalid_argument("tet " + std::to_string(t) + " has label " +
                                  std::to_string(label) + " without a material (" +
                                  std::to_string(materials.size()) + " materials given)");
    }
    const ElementMaterial& m = materials[static_cast<std::size_t>(label)];
    for (int k = 0; k < 4; ++k) {
      const int node = mesh.tets(t, k);
      if (node < 0 || node >= mesh.num_nodes())
        throw std::invalid_argument("tet " + std::to_string(t) + " has node index " +
                                    std::to_string(node) + " outside [0, " +
                                    std::to_string(mesh.num_nodes()) + ")");
    }
    const Mat3 dm = edge_matrix(mesh.rest, mesh.tets, t);
    const Real volume = dm.determinant() / 6;
    if (!(volume > 0)) {
      throw std::invalid_argument("tet " + std::to_string(t) + " has non-positive rest volume " +
                                  std::to_string(volume));
    }
    e.rest_volume(t) = volume;
    e.rest_inverse[static_cast<std::size_t>(t)] = dm.inverse();
    e.lame[static_cast<std::size_t>(t)] = lame_from_youngs(m.youngs_modulus, m.poisson_ratio);
    e.youngs_modulus(t) = m.youngs_modulus;
    e.damping(t) = m.damping;
    e.density(t) = m.density;
    for (int k = 0; k < 4; ++k)
      e.masses(mesh.tets(t, k)) += m.density * volume / 4;
  }
  return e;
}

void add_consistent_mass_triplets(const TetElements& elements,
                                  std::vector<Eigen::Triplet<Real>>& triplets) {
  for (int t = 0; t < elements.num_tets(); ++t) {
    const Real m = elements.density(t) * elements.rest_volume(t) / 20;
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) {
        const Real value = a == b ? 2 * m : m;
        for (int c = 0; c < 3; ++c)
          triplets.emplace_back(3 * elements.tets(t, a) + c, 3 * elements.tets(t, b) + c, value);
      }
    }
  }
}

}  // namespace incise::sim
