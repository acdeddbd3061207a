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

namespace {

// Checks tet t of mesh and returns its material's index (its label).
int checked_label(const TetMesh& mesh, int t, const std::vector<ElementMaterial>& materials) {
  const int label = mesh.labels.size() == 0 ? 0 : mesh.labels(t);
  if (label < 0 || label >= static_cast<int>(materials.size())) {
    throw std::invalid_argument("tet " + std::to_string(t) + " has label " + std::to_string(label) +
                                " without a material (" + std::to_string(materials.size()) +
                                " materials given)");
  }
  for (int k = 0; k < 4; ++k) {
    const int node = mesh.tets(t, k);
    if (node < 0 || node >= mesh.num_nodes())
      throw std::invalid_argument("tet " + std::to_string(t) + " has node index " +
                                  std::to_string(node) + " outside [0, " +
                                  std::to_string(mesh.num_nodes()) + ")");
  }
  const Real volume = edge_matrix(mesh.rest, mesh.tets, t).determinant() / 6;
  if (!(volume > 0)) {
    throw std::invalid_argument("tet " + std::to_string(t) + " has non-positive rest volume " +
                                std::to_string(volume));
  }
  return label;
}

// Fills slot t of e from tet t of mesh (checked) and adds its mass to its nodes.
void fill_element(TetElements& e, const TetMesh& mesh, int t, const ElementMaterial& m) {
  const std::size_t ts = static_cast<std::size_t>(t);
  e.tets.row(t) = mesh.tets.row(t);
  const Mat3 dm = edge_matrix(mesh.rest, mesh.tets, t);
  const Real volume = dm.determinant() / 6;
  e.rest_volume(t) = volume;
  e.rest_inverse[ts] = dm.inverse();
  e.lame[ts] = lame_from_youngs(m.youngs_modulus, m.poisson_ratio);
  e.youngs_modulus(t) = m.youngs_modulus;
  e.damping(t) = m.damping;
  e.density(t) = m.density;
  e.alive_slots[ts] = 1;
  for (int k = 0; k < 4; ++k) {
    e.masses(mesh.tets(t, k)) += m.density * volume / 4;
    ++e.node_elements[static_cast<std::size_t>(mesh.tets(t, k))];
  }
}

// Resizes the per-tet arrays to `slots`, keeping what is there; new slots are empty.
void resize_slots(TetElements& e, int slots) {
  const int old = e.num_tets();
  if (slots <= old) return;
  e.tets.conservativeResize(slots, 4);
  e.tets.bottomRows(slots - old).setZero();
  for (VecX* v : {&e.rest_volume, &e.youngs_modulus, &e.damping, &e.density}) {
    v->conservativeResize(slots);
    v->tail(slots - old).setZero();
  }
  e.rest_inverse.resize(static_cast<std::size_t>(slots), Mat3::Zero());
  e.lame.resize(static_cast<std::size_t>(slots));
  e.alive_slots.resize(static_cast<std::size_t>(slots), 0);
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
  e.masses = VecX::Zero(mesh.num_nodes());
  e.node_elements.assign(static_cast<std::size_t>(mesh.num_nodes()), 0);
  resize_slots(e, num_tets);
  for (int t = 0; t < num_tets; ++t) {
    const int label = checked_label(mesh, t, materials);
    fill_element(e, mesh, t, materials[static_cast<std::size_t>(label)]);
  }
  return e;
}

void update_tet_elements(TetElements& e, const TetMesh& mesh, const std::vector<char>& alive,
                         std::span<const int> changed,
                         const std::vector<ElementMaterial>& materials) {
  const int slots = mesh.num_tets();
  if (alive.size() != static_cast<std::size_t>(slots) ||
      (mesh.labels.size() != 0 && mesh.labels.size() != slots)) {
    throw std::invalid_argument(
        "update_tet_elements: alive and labels must have one entry per "
        "tet slot");
  }
  std::vector<int> labels(changed.size(), -1);
  for (std::size_t c = 0; c < changed.size(); ++c) {
    const int t = changed[c];
    if (t < 0 || t >= slots) {
      throw std::invalid_argument("update_tet_elements: slot " + std::to_string(t) +
                                  " outside [0, " + std::to_string(slots) + ")");
    }
    if (alive[static_cast<std::size_t>(t)] != 0) labels[c] = checked_label(mesh, t, materials);
  }
  resize_slots(e, slots);
  if (e.masses.size() < mesh.num_nodes()) {
    const Eigen::Index old = e.masses.size();
    e.masses.conservativeResize(mesh.num_nodes());
    e.masses.tail(mesh.num_nodes() - old).setZero();
  }
  e.node_elements.resize(static_cast<std::size_t>(mesh.num_nodes()), 0);
  // First every leaving element, then every arriving one (a slot may be in both).
  for (const int t : changed) {
    if (!e.alive(t)) continue;
    const Real quarter = e.density(t) * e.rest_volume(t) / 4;
    for (int k = 0; k < 4; ++k) {
      const int node = e.tets(t, k);
      e.masses(node) -= quarter;
      // The round-off of the subtractions must not leave a mass on a node without elements.
      if (--e.node_elements[static_cast<std::size_t>(node)] == 0) e.masses(node) = 0;
    }
    e.alive_slots[static_cast<std::size_t>(t)] = 0;
  }
  for (std::size_t c = 0; c < changed.size(); ++c) {
    if (labels[c] < 0) continue;
    fill_element(e, mesh, changed[c], materials[static_cast<std::size_t>(labels[c])]);
  }
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
