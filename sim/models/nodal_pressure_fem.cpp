#include "sim/models/nodal_pressure_fem.h"

#include <algorithm>
#include <utility>

namespace incise::sim {

namespace {

Real bulk_modulus(const Lame& lame) {
  return lame.lambda + Real(2) / 3 * lame.mu;
}

// d theta_e / dx for tet t: node a's block is R grad N_a (grad N_k = row k - 1 of Dm^-1, grad N_0
// their negated sum), as the 3 x 4 matrix of those columns.
Eigen::Matrix<Real, 3, 4> volume_gradient(const TetElements& e, int t, const Mat3& rotation) {
  Eigen::Matrix<Real, 3, 4> g;
  g.rightCols<3>() = rotation * e.rest_inverse[static_cast<std::size_t>(t)].transpose();
  g.col(0) = -g.rightCols<3>().rowwise().sum();
  return g;
}

}  // namespace

NodalPressureFem::NodalPressureFem(const TetMesh& mesh, std::vector<ElementMaterial> materials)
    : CorotationalFem(mesh, std::move(materials), RotationExtraction::polar) {
  softened_.assign(static_cast<std::size_t>(elements().num_tets()), 0);
  rotation_.assign(softened_.size(), Mat3::Identity());
  refresh_nodes();
  prepare_stiffness(mesh.rest);
}

std::string_view NodalPressureFem::name() const {
  return "corotational_nodal_pressure";
}

bool NodalPressureFem::averaged(int t) const {
  return elements().alive(t) && softened_[static_cast<std::size_t>(t)] == 0;
}

void NodalPressureFem::refresh_nodes() {
  const TetElements& e = elements();
  node_weight_.setZero(e.num_nodes());
  node_kappa_.setZero(e.num_nodes());
  for (int t = 0; t < e.num_tets(); ++t) {
    if (!averaged(t)) continue;
    const Real quarter = e.rest_volume(t) / 4;
    const Real kappa = bulk_modulus(e.lame[static_cast<std::size_t>(t)]);
    for (int a = 0; a < 4; ++a) {
      node_weight_(e.tets(t, a)) += quarter;
      node_kappa_(e.tets(t, a)) += quarter * kappa;
    }
  }
  for (int n = 0; n < e.num_nodes(); ++n)
    node_kappa_(n) = node_weight_(n) > 0 ? node_kappa_(n) / node_weight_(n) : 0;
  theta_.assign(static_cast<std::size_t>(e.num_tets()), 0);
  pressure_.setZero(e.num_nodes());
  rotation_.resize(static_cast<std::size_t>(e.num_tets()), Mat3::Identity());
  stiff_rotation_.resize(static_cast<std::size_t>(e.num_tets()), Mat3::Identity());
}

void NodalPressureFem::add_correction(const Points& u, std::span<const Mat3> rotations, Real offset,
                                      Real sign, Points& out) const {
  const TetElements& e = elements();
  pressure_.setZero();
  for (int t = 0; t < e.num_tets(); ++t) {
    if (!averaged(t)) continue;
    const std::size_t ts = static_cast<std::size_t>(t);
    const Mat3 deformation = edge_matrix(u, e.tets, t) * e.rest_inverse[ts];
    theta_[ts] = rotations[ts].cwiseProduct(deformation).sum() - offset;  // tr(R^T F) - offset
    const Real share = e.rest_volume(t) / 4 * theta_[ts];
    for (int a = 0; a < 4; ++a)
      pressure_(e.tets(t, a)) += share;
  }
  for (int n = 0; n < e.num_nodes(); ++n)
    pressure_(n) = node_weight_(n) > 0 ? node_kappa_(n) * pressure_(n) / node_weight_(n) : 0;
  for (int t = 0; t < e.num_tets(); ++t) {
    if (!averaged(t)) continue;
    const std::size_t ts = static_cast<std::size_t>(t);
    const Real mean = Real(0.25) * (pressure_(e.tets(t, 0)) + pressure_(e.tets(t, 1)) +
                                    pressure_(e.tets(t, 2)) + pressure_(e.tets(t, 3)));
    scatter_stress(e, t, sign * (mean - bulk_modulus(e.lame[ts]) * theta_[ts]) * rotations[ts],
                   out);
  }
}

void NodalPressureFem::add_forces(const Points& x, const Points& v, Points& f) {
  CorotationalFem::add_forces(x, v, f);
  const TetElements& e = elements();
  for (int t = 0; t < e.num_tets(); ++t) {
    if (averaged(t)) rotation_[static_cast<std::size_t>(t)] = batch().rotation(t);
  }
  add_correction(x, rotation_, 3, 1, f);
}

void NodalPressureFem::prepare_stiffness(const Points& x) {
  CorotationalFem::prepare_stiffness(x);
  const TetElements& e = elements();
  stiff_rotation_.resize(static_cast<std::size_t>(e.num_tets()), Mat3::Identity());
  for (int t = 0; t < e.num_tets(); ++t) {
    if (!e.alive(t)) continue;
    stiff_rotation_[static_cast<std::size_t>(t)] =
        polar_rotation(edge_matrix(x, e.tets, t) * e.rest_inverse[static_cast<std::size_t>(t)]);
  }
}

void NodalPressureFem::add_stiffness_times(const Points& dx, Points& out) const {
  CorotationalFem::add_stiffness_times(dx, out);
  // K dx of the correction: the same pass on d theta_e = tr(R_e^T dF_e) (linear: no offset), its
  // force negated (K = -df/dx).
  add_correction(dx, stiff_rotation_, 0, -1, out);
}

void NodalPressureFem::add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const {
  CorotationalFem::add_stiffness_triplets(triplets);
  const TetElements& e = elements();
  // - sum_e kappa_e V_e g_e g_e^T
  for (int t = 0; t < e.num_tets(); ++t) {
    if (!averaged(t)) continue;
    const std::size_t ts = static_cast<std::size_t>(t);
    const auto g = volume_gradient(e, t, stiff_rotation_[ts]);
    const Real scale = -bulk_modulus(e.lame[ts]) * e.rest_volume(t);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            triplets.emplace_back(3 * e.tets(t, a) + r, 3 * e.tets(t, b) + c,
                                  scale * g(r, a) * g(c, b));
  }
  // + sum_n (K_n / W_n) G_n G_n^T, G_n gathered per node over its elements.
  std::vector<std::pair<int, int>> node_tets;  // (node, tet), sorted by node
  for (int t = 0; t < e.num_tets(); ++t) {
    if (!averaged(t)) continue;
    for (int a = 0; a < 4; ++a)
      node_tets.emplace_back(e.tets(t, a), t);
  }
  std::sort(node_tets.begin(), node_tets.end());
  std::vector<std::pair<int, Vec3>> entries;  // G_n's blocks, per node (duplicates summed below)
  for (std::size_t i = 0; i < node_tets.size();) {
    const int n = node_tets[i].first;
    entries.clear();
    for (; i < node_tets.size() && node_tets[i].first == n; ++i) {
      const int t = node_tets[i].second;
      const auto g = volume_gradient(e, t, stiff_rotation_[static_cast<std::size_t>(t)]);
      for (int a = 0; a < 4; ++a)
        entries.emplace_back(e.tets(t, a), e.rest_volume(t) / 4 * g.col(a));
    }
    std::sort(entries.begin(), entries.end(),
              [](const auto& p, const auto& q) { return p.first < q.first; });
    std::size_t merged = 0;
    for (std::size_t k = 0; k < entries.size(); ++k) {
      if (merged > 0 && entries[merged - 1].first == entries[k].first) {
        entries[merged - 1].second += entries[k].second;
      } else {
        entries[merged++] = entries[k];
      }
    }
    const Real scale = node_weight_(n) > 0 ? node_kappa_(n) / node_weight_(n) : 0;
    for (std::size_t p = 0; p < merged; ++p)
      for (std::size_t q = 0; q < merged; ++q)
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            triplets.emplace_back(3 * entries[p].first + r, 3 * entries[q].first + c,
                                  scale * entries[p].second(r) * entries[q].second(c));
  }
}

void NodalPressureFem::system_blocks(std::vector<std::pair<int, int>>& blocks) const {
  Model::system_blocks(blocks);  // the nodal coupling reaches beyond one tet's node pairs
}

void NodalPressureFem::add_system_blocks(Real damping_scale, Real stiffness_scale,
                                         const BlockTarget& target) const {
  Model::add_system_blocks(damping_scale, stiffness_scale, target);
}

Real NodalPressureFem::potential_energy(const Points& x) const {
  Real energy = CorotationalFem::potential_energy(x);
  const TetElements& e = elements();
  std::vector<Mat3> rotations(static_cast<std::size_t>(e.num_tets()), Mat3::Identity());
  for (int t = 0; t < e.num_tets(); ++t) {
    if (!averaged(t)) continue;
    rotations[static_cast<std::size_t>(t)] =
        polar_rotation(edge_matrix(x, e.tets, t) * e.rest_inverse[static_cast<std::size_t>(t)]);
  }
  // Replace each averaged element's V_e kappa_e theta_e^2 / 2 by the nodes' W_n K_n theta_n^2 / 2.
  VecX theta_n = VecX::Zero(e.num_nodes());
  for (int t = 0; t < e.num_tets(); ++t) {
    if (!averaged(t)) continue;
    const std::size_t ts = static_cast<std::size_t>(t);
    const Mat3 deformation = edge_matrix(x, e.tets, t) * e.rest_inverse[ts];
    const Real theta = rotations[ts].cwiseProduct(deformation).sum() - 3;
    energy -= e.rest_volume(t) * bulk_modulus(e.lame[ts]) * theta * theta / 2;
    for (int a = 0; a < 4; ++a)
      theta_n(e.tets(t, a)) += e.rest_volume(t) / 4 * theta;
  }
  for (int n = 0; n < e.num_nodes(); ++n) {
    if (!(node_weight_(n) > 0)) continue;
    const Real theta = theta_n(n) / node_weight_(n);
    energy += node_weight_(n) * node_kappa_(n) * theta * theta / 2;
  }
  return energy;
}

void NodalPressureFem::update_topology(const TetMesh& mesh) {
  CorotationalFem::update_topology(mesh);
  softened_.assign(static_cast<std::size_t>(elements().num_tets()), 0);
  rotation_.assign(softened_.size(), Mat3::Identity());
  refresh_nodes();
  prepare_stiffness(mesh.rest);
}

void NodalPressureFem::update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                                       std::span<const int> changed) {
  CorotationalFem::update_elements(mesh, alive, changed);
  softened_.resize(static_cast<std::size_t>(elements().num_tets()), 0);
  rotation_.resize(softened_.size(), Mat3::Identity());
  stiff_rotation_.resize(softened_.size(), Mat3::Identity());
  for (const int t : changed) {
    const std::size_t ts = static_cast<std::size_t>(t);
    softened_[ts] = 0;
    rotation_[ts] = Mat3::Identity();
    stiff_rotation_[ts] = Mat3::Identity();
  }
  refresh_nodes();
}

bool NodalPressureFem::soften_element(int t, Real factor) {
  if (!CorotationalFem::soften_element(t, factor)) return false;
  softened_[static_cast<std::size_t>(t)] = 1;
  // Leaving the averages changes which nodes the stiffness couples: a solver keeping a sparsity
  // pattern must see a new one.
  topology_changed();
  refresh_nodes();
  return true;
}

}  // namespace incise::sim
