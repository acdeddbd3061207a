// The hybrid condensed model's construction and its forces, products and blocks. Its parts are in
// hybrid_condensed_partition, _schur_complement and _topology (.cpp).
#include "sim/models/hybrid_condensed_model.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/models/hybrid_condensed_partition.h"

namespace incise::sim {

HybridCondensedModel::HybridCondensedModel(const TetMesh& mesh,
                                           const std::vector<char>& operational,
                                           const std::vector<ElementMaterial>& materials,
                                           const RegionModelFactory& make_operational) {
  if (operational.size() != static_cast<std::size_t>(mesh.num_tets())) {
    throw std::invalid_argument(where("operational flags must have one entry per tet (got ") +
                                std::to_string(operational.size()) + " for " +
                                std::to_string(mesh.num_tets()) + " tets)");
  }
  if (std::none_of(operational.begin(), operational.end(), [](char o) { return o != 0; })) {
    throw std::invalid_argument(where("no operational tet (flag at least one tet operational)"));
  }
  if (!make_operational) throw std::invalid_argument(where("no operational model factory"));

  operational_ = make_operational(region_mesh(mesh, operational, true), materials);
  if (!operational_) throw std::invalid_argument(where("the operational factory made no model"));

  rest_ = mesh.rest;
  const TetMesh far = region_mesh(mesh, operational, false);
  far_tets_.resize(far.num_tets(), 4);
  for (int t = 0; t < far.num_tets(); ++t)
    far_tets_.row(t) = sorted_tet(far.tets, t);

  const std::vector<int> local = partition_nodes(mesh, far, operational);
  const Eigen::Index s_dofs = 3 * static_cast<Eigen::Index>(retained_.size());
  const Eigen::Index i_dofs = 3 * static_cast<Eigen::Index>(interior_.size());
  condense_far_field(far, materials, local, s_dofs, i_dofs);
  u_s_.resize(s_dofs);
  y_s_.resize(s_dofs);

  slot_operational_ = operational;
  operational_slot_.assign(operational.size(), -1);
  for (std::size_t t = 0; t < operational.size(); ++t) {
    if (operational[t] == 0) continue;
    operational_slot_[t] = static_cast<int>(global_slot_.size());
    global_slot_.push_back(static_cast<int>(t));
  }
  operational_view_ = region_mesh(mesh, operational, true);
  rebuild_masses();
}

void HybridCondensedModel::rebuild_masses() {
  masses_ = operational_->masses();
  masses_.head(far_masses_.size()) += far_masses_;
}

void HybridCondensedModel::gather(const Points& p, bool minus_rest, VecX& out) const {
  for (std::size_t k = 0; k < retained_.size(); ++k) {
    const int i = retained_[k];
    const Eigen::Index r = 3 * static_cast<Eigen::Index>(k);
    out.segment<3>(r) = p.row(i).transpose();
    if (minus_rest) out.segment<3>(r) -= rest_.row(i).transpose();
  }
}

void HybridCondensedModel::scatter_add(const VecX& y, Real scale, Points& out) const {
  for (std::size_t k = 0; k < retained_.size(); ++k) {
    out.row(retained_[k]) += scale * y.segment<3>(3 * static_cast<Eigen::Index>(k)).transpose();
  }
}

void HybridCondensedModel::add_forces(const Points& x, const Points& v, Points& f) {
  operational_->add_forces(x, v, f);
  if (retained_.empty()) return;
  gather(x, true, u_s_);
  if (far_beta_ > 0) {
    // K* u + beta K* v = K* (u + beta v)
    gather(v, false, y_s_);
    u_s_ += far_beta_ * y_s_;
  }
  y_s_.noalias() = k_star_ * u_s_;
  if (d_star_.size() > 0) {
    gather(v, false, u_s_);
    y_s_.noalias() += d_star_ * u_s_;
  }
  scatter_add(y_s_, -1, f);
}

void HybridCondensedModel::prepare_stiffness(const Points& x) {
  operational_->prepare_stiffness(x);
}

void HybridCondensedModel::add_stiffness_times(const Points& dx, Points& out) const {
  operational_->add_stiffness_times(dx, out);
  if (retained_.empty()) return;
  gather(dx, false, u_s_);
  y_s_.noalias() = k_star_ * u_s_;
  scatter_add(y_s_, 1, out);
}

void HybridCondensedModel::add_damping_times(const Points& dv, Points& out) const {
  operational_->add_damping_times(dv, out);
  if (far_beta_ > 0) {
    gather(dv, false, u_s_);
    y_s_.noalias() = k_star_ * u_s_;
    scatter_add(y_s_, far_beta_, out);
  } else if (d_star_.size() > 0) {
    gather(dv, false, u_s_);
    y_s_.noalias() = d_star_ * u_s_;
    scatter_add(y_s_, 1, out);
  }
}

namespace {

void add_dense_triplets(const Eigen::MatrixXd& m, const std::vector<int>& nodes,
                        std::vector<Eigen::Triplet<Real>>& triplets) {
  for (Eigen::Index c = 0; c < m.cols(); ++c) {
    const int column = 3 * nodes[static_cast<std::size_t>(c / 3)] + static_cast<int>(c % 3);
    for (Eigen::Index r = 0; r < m.rows(); ++r) {
      triplets.emplace_back(3 * nodes[static_cast<std::size_t>(r / 3)] + static_cast<int>(r % 3),
                            column, m(r, c));
    }
  }
}

}  // namespace

void HybridCondensedModel::add_stiffness_triplets(
    std::vector<Eigen::Triplet<Real>>& triplets) const {
  operational_->add_stiffness_triplets(triplets);
  add_dense_triplets(k_star_, retained_, triplets);
}

void HybridCondensedModel::add_damping_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const {
  operational_->add_damping_triplets(triplets);
  if (far_beta_ > 0) {
    add_dense_triplets(far_beta_ * k_star_, retained_, triplets);
  } else {
    add_dense_triplets(d_star_, retained_, triplets);
  }
}

void HybridCondensedModel::system_blocks(std::vector<std::pair<int, int>>& blocks) const {
  for (std::size_t k = 0; k < retained_.size(); ++k) {
    for (std::size_t l = 0; l <= k; ++l)
      blocks.emplace_back(retained_[k], retained_[l]);
  }
  operational_->system_blocks(blocks);
}

void HybridCondensedModel::add_system_blocks(Real damping_scale, Real stiffness_scale,
                                             const BlockTarget& target) const {
  std::size_t block = 0;
  for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(retained_.size()); ++k) {
    for (Eigen::Index l = 0; l <= k; ++l) {
      Mat3 value =
          (stiffness_scale + damping_scale * far_beta_) * k_star_.block<3, 3>(3 * k, 3 * l);
      if (d_star_.size() > 0) value += damping_scale * d_star_.block<3, 3>(3 * k, 3 * l);
      target.add(block++, value);
    }
  }
  operational_->add_system_blocks(damping_scale, stiffness_scale,
                                  BlockTarget{target.values, target.slots + block});
}

Real HybridCondensedModel::potential_energy(const Points& x) const {
  Real energy = operational_->potential_energy(x);
  if (retained_.empty()) return energy;
  gather(x, true, u_s_);
  y_s_.noalias() = k_star_ * u_s_;
  return energy + Real(0.5) * u_s_.dot(y_s_);
}

Eigen::MatrixXd HybridCondensedModel::condensed_damping() const {
  if (far_beta_ > 0) return far_beta_ * k_star_;
  return d_star_;
}

void HybridCondensedModel::recover_interior(Points& x) const {
  if (x.rows() < rest_.rows()) {
    throw std::invalid_argument(where("recover_interior: x has fewer rows than the model's nodes"));
  }
  if (interior_.empty()) return;
  VecX u_s(3 * static_cast<Eigen::Index>(retained_.size()));
  gather(x, true, u_s);
  const VecX u_i = -interior_solver_->solve(VecX(k_is_ * u_s));
  for (std::size_t k = 0; k < interior_.size(); ++k) {
    const int i = interior_[k];
    x.row(i) = rest_.row(i) + u_i.segment<3>(3 * static_cast<Eigen::Index>(k)).transpose();
  }
}

HybridCondensedModel::HybridCondensedModel(const HybridCondensedModel& other)
    : Model(other),
      rest_(other.rest_),
      far_tets_(other.far_tets_),
      condensed_(other.condensed_),
      retained_(other.retained_),
      interior_(other.interior_),
      k_star_(other.k_star_),
      far_beta_(other.far_beta_),
      d_star_(other.d_star_),
      far_masses_(other.far_masses_),
      masses_(other.masses_),
      interior_solver_(other.interior_solver_),
      k_is_(other.k_is_),
      slot_operational_(other.slot_operational_),
      operational_slot_(other.operational_slot_),
      global_slot_(other.global_slot_),
      operational_view_(other.operational_view_),
      u_s_(other.u_s_),
      y_s_(other.y_s_) {}

std::unique_ptr<Model> HybridCondensedModel::clone() const {
  auto copy = std::unique_ptr<HybridCondensedModel>(new HybridCondensedModel(*this));
  copy->operational_ = operational_->clone();
  return copy;
}

}  // namespace incise::sim
