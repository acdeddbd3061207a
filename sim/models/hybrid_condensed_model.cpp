#include "sim/models/hybrid_condensed_model.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/mesh/boundary_surface.h"
#include "sim/models/linear_fem.h"

namespace incise::sim {
namespace {

using SparseMatrix = Eigen::SparseMatrix<Real>;
using Triplets = std::vector<Eigen::Triplet<Real>>;

// Columns of K* computed per batch of solves: bounds the dense Kii^-1 Kis work array to
// 3 #interior x kBatch doubles.
constexpr Eigen::Index kBatch = 64;

std::string where(const char* what) {
  return std::string("HybridCondensedModel: ") + what;
}

// A tet's nodes sorted ascending: the same tet whatever its row's node order.
Eigen::RowVector4i sorted_tet(const Tets& tets, Eigen::Index row) {
  Eigen::RowVector4i t = tets.row(row);
  std::sort(t.data(), t.data() + 4);
  return t;
}

bool tet_less(const Eigen::RowVector4i& a, const Eigen::RowVector4i& b) {
  return std::lexicographical_compare(a.data(), a.data() + 4, b.data(), b.data() + 4);
}

// The mesh's rest state with only the tets whose flag equals `keep`.
TetMesh region_mesh(const TetMesh& mesh, const std::vector<char>& operational, bool keep) {
  TetMesh region;
  region.rest = mesh.rest;
  region.x = mesh.rest;
  region.v = Points::Zero(mesh.rest.rows(), 3);
  const auto count = std::count_if(operational.begin(), operational.end(),
                                   [keep](char o) { return (o != 0) == keep; });
  region.tets.resize(count, 4);
  region.labels.resize(count);
  Eigen::Index row = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if ((operational[static_cast<std::size_t>(t)] != 0) != keep) continue;
    region.tets.row(row) = mesh.tets.row(t);
    region.labels(row) = mesh.labels.size() == 0 ? 0 : mesh.labels(t);
    ++row;
  }
  return region;
}

// The far field's matrix (K or D, over all mesh degrees of freedom) split by the local numbering
// `local` (retained dofs first, then interior ones; -1 outside the far field).
struct Partition {
  Eigen::MatrixXd ss;
  SparseMatrix si, is, ii;
};

Partition partition(const Triplets& entries, const std::vector<int>& local, Eigen::Index s_dofs,
                    Eigen::Index i_dofs) {
  Partition p;
  p.ss = Eigen::MatrixXd::Zero(s_dofs, s_dofs);
  Triplets si, is, ii;
  for (const auto& e : entries) {
    const int r = local[static_cast<std::size_t>(e.row())];
    const int c = local[static_cast<std::size_t>(e.col())];
    if (r < 0 || c < 0) continue;
    if (r < s_dofs && c < s_dofs) {
      p.ss(r, c) += e.value();
    } else if (r < s_dofs) {
      si.emplace_back(r, c - s_dofs, e.value());
    } else if (c < s_dofs) {
      is.emplace_back(r - s_dofs, c, e.value());
    } else {
      ii.emplace_back(r - s_dofs, c - s_dofs, e.value());
    }
  }
  p.si.resize(s_dofs, i_dofs);
  p.is.resize(i_dofs, s_dofs);
  p.ii.resize(i_dofs, i_dofs);
  p.si.setFromTriplets(si.begin(), si.end());
  p.is.setFromTriplets(is.begin(), is.end());
  p.ii.setFromTriplets(ii.begin(), ii.end());
  return p;
}

}  // namespace

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

  const int n = mesh.num_nodes();
  rest_ = mesh.rest;
  const TetMesh far = region_mesh(mesh, operational, false);
  far_tets_.resize(far.num_tets(), 4);
  for (int t = 0; t < far.num_tets(); ++t)
    far_tets_.row(t) = sorted_tet(far.tets, t);

  // Retained: far-field nodes on the body's surface or on an operational tet.
  std::vector<char> in_far(static_cast<std::size_t>(n), 0), keep(static_cast<std::size_t>(n), 0);
  for (int t = 0; t < far.num_tets(); ++t) {
    for (int a = 0; a < 4; ++a)
      in_far[static_cast<std::size_t>(far.tets(t, a))] = 1;
  }
  for (const int node : boundary_surface(mesh).nodes)
    keep[static_cast<std::size_t>(node)] = 1;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (operational[static_cast<std::size_t>(t)] == 0) continue;
    for (int a = 0; a < 4; ++a)
      keep[static_cast<std::size_t>(mesh.tets(t, a))] = 1;
  }
  condensed_.assign(static_cast<std::size_t>(n), 0);
  for (int i = 0; i < n; ++i) {
    const std::size_t is = static_cast<std::size_t>(i);
    if (in_far[is] == 0) continue;
    if (keep[is] != 0) {
      retained_.push_back(i);
    } else {
      interior_.push_back(i);
      condensed_[is] = 1;
    }
  }
  const Eigen::Index s_dofs = 3 * static_cast<Eigen::Index>(retained_.size());
  const Eigen::Index i_dofs = 3 * static_cast<Eigen::Index>(interior_.size());
  std::vector<int> local(3 * static_cast<std::size_t>(n), -1);
  for (std::size_t k = 0; k < retained_.size(); ++k) {
    for (int c = 0; c < 3; ++c)
      local[3 * static_cast<std::size_t>(retained_[k]) + c] = static_cast<int>(3 * k) + c;
  }
  for (std::size_t k = 0; k < interior_.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      local[3 * static_cast<std::size_t>(interior_[k]) + c] =
          static_cast<int>(s_dofs + 3 * static_cast<Eigen::Index>(k)) + c;
    }
  }

  // The far field's K, D (= beta K per tet) and lumped masses from the linear FEM.
  far_masses_ = VecX::Zero(n);
  k_star_.resize(0, 0);
  d_star_.resize(0, 0);
  if (far.num_tets() > 0) {
    const LinearFem linear(far, materials);
    Triplets k_entries, d_entries;
    linear.add_stiffness_triplets(k_entries);
    linear.add_damping_triplets(d_entries);
    const VecX& beta = linear.elements().damping;
    // One viscosity over the far field (the usual case): D* = beta K*, one dense matrix fewer
    // and one matrix-vector product per force evaluation instead of two.
    const bool uniform = (beta.array() == beta(0)).all();
    if (uniform) far_beta_ = beta(0);
    const bool damped = !uniform && (beta.array() > 0).any();
    const Partition k = partition(k_entries, local, s_dofs, i_dofs);
    const Partition d = damped ? partition(d_entries, local, s_dofs, i_dofs) : Partition{};
    k_star_ = k.ss;
    if (damped) d_star_ = d.ss;
    if (i_dofs > 0) {
      interior_solver_.compute(k.ii);
      if (interior_solver_.info() != Eigen::Success ||
          !(interior_solver_.vectorD().minCoeff() > 0)) {
        throw std::invalid_argument(
            where("the far field's interior stiffness Kii is not positive definite (degenerate "
                  "far-field tets?)"));
      }
      k_is_ = k.is;
      // Per batch b of columns: X_b = Kii^-1 Kis_b (= -T_b), K*_b = Kss_b - Ksi X_b and, with
      // T^T y = -Ksi Kii^-1 y, D*_b = Dss_b - Dsi X_b - Ksi Kii^-1 (Dis_b - Dii X_b).
      for (Eigen::Index b = 0; b < s_dofs; b += kBatch) {
        const Eigen::Index w = std::min(kBatch, s_dofs - b);
        const Eigen::MatrixXd x_b = interior_solver_.solve(Eigen::MatrixXd(k.is.middleCols(b, w)));
        k_star_.middleCols(b, w).noalias() -= k.si * x_b;
        if (damped) {
          const Eigen::MatrixXd y_b = Eigen::MatrixXd(d.is.middleCols(b, w)) - d.ii * x_b;
          d_star_.middleCols(b, w).noalias() -= d.si * x_b;
          d_star_.middleCols(b, w).noalias() -= k.si * interior_solver_.solve(y_b);
        }
      }
    }
    // Lump the far field's mass onto its retained nodes, scaled to keep its total.
    const VecX& lumped = linear.masses();
    Real retained_share = 0;
    for (const int i : retained_)
      retained_share += lumped(i);
    const Real scale = lumped.sum() / retained_share;
    for (const int i : retained_)
      far_masses_(i) = scale * lumped(i);
  }
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

void HybridCondensedModel::check_operational_tet(const Tets& tets, int row) const {
  for (int a = 0; a < 4; ++a) {
    const int node = tets(row, a);
    if (node >= 0 && static_cast<std::size_t>(node) < condensed_.size() &&
        condensed_[static_cast<std::size_t>(node)] != 0) {
      throw std::invalid_argument(where("operational tet ") + std::to_string(row) +
                                  " uses condensed interior node " + std::to_string(node));
    }
  }
}

void HybridCondensedModel::update_topology(const TetMesh& mesh) {
  std::vector<char> operational(static_cast<std::size_t>(mesh.num_tets()), 1);
  std::vector<char> found(static_cast<std::size_t>(far_tets_.rows()), 0);
  std::vector<Eigen::Index> order(static_cast<std::size_t>(far_tets_.rows()));
  for (std::size_t k = 0; k < order.size(); ++k)
    order[k] = static_cast<Eigen::Index>(k);
  std::sort(order.begin(), order.end(), [this](Eigen::Index a, Eigen::Index b) {
    return tet_less(far_tets_.row(a), far_tets_.row(b));
  });
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Eigen::RowVector4i key = sorted_tet(mesh.tets, t);
    const auto it = std::lower_bound(order.begin(), order.end(), key,
                                     [this](Eigen::Index a, const Eigen::RowVector4i& k) {
                                       return tet_less(far_tets_.row(a), k);
                                     });
    if (it != order.end() && far_tets_.row(*it) == key) {
      found[static_cast<std::size_t>(*it)] = 1;
      operational[static_cast<std::size_t>(t)] = 0;
    } else {
      check_operational_tet(mesh.tets, t);
    }
  }
  const auto missing = std::find(found.begin(), found.end(), 0);
  if (missing != found.end()) {
    throw std::invalid_argument(where("update_topology: far-field tet ") +
                                std::to_string(missing - found.begin()) +
                                " is missing (the condensed region is fixed)");
  }
  operational_view_ = region_mesh(mesh, operational, true);
  operational_->update_topology(operational_view_);
  slot_operational_ = operational;
  operational_slot_.assign(operational.size(), -1);
  global_slot_.clear();
  for (std::size_t t = 0; t < operational.size(); ++t) {
    if (operational[t] == 0) continue;
    operational_slot_[t] = static_cast<int>(global_slot_.size());
    global_slot_.push_back(static_cast<int>(t));
  }
  rebuild_masses();
  topology_changed();
}

void HybridCondensedModel::update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                                           std::span<const int> changed) {
  const std::size_t slots = static_cast<std::size_t>(mesh.num_tets());
  const std::size_t old_slots = slot_operational_.size();
  if (alive.size() != slots) {
    throw std::invalid_argument(where("update_elements: alive must have one entry per tet slot"));
  }
  if (slots < old_slots) {
    throw std::invalid_argument(where("update_elements: the mesh has fewer tet slots (") +
                                std::to_string(slots) + ") than the model (" +
                                std::to_string(old_slots) + ")");
  }
  for (std::size_t t = 0; t < old_slots; ++t) {
    if (slot_operational_[t] == 0 && alive[t] == 0) {
      throw std::invalid_argument(where("update_elements: far-field slot ") + std::to_string(t) +
                                  " is not alive (the condensed region is fixed)");
    }
  }
  for (const int s : changed) {
    if (s < 0 || static_cast<std::size_t>(s) >= slots) {
      throw std::invalid_argument(where("update_elements: changed slot ") + std::to_string(s) +
                                  " is out of range");
    }
    if (static_cast<std::size_t>(s) < old_slots &&
        slot_operational_[static_cast<std::size_t>(s)] == 0) {
      throw std::invalid_argument(where("update_elements: slot ") + std::to_string(s) +
                                  " is in the condensed region, which is fixed");
    }
    if (alive[static_cast<std::size_t>(s)] != 0) check_operational_tet(mesh.tets, s);
  }

  // New global slots become new operational slots, in order.
  std::vector<int> operational_slot = operational_slot_;
  std::vector<int> global_slot = global_slot_;
  operational_slot.resize(slots, -1);
  for (std::size_t t = old_slots; t < slots; ++t) {
    operational_slot[t] = static_cast<int>(global_slot.size());
    global_slot.push_back(static_cast<int>(t));
  }
  const Eigen::Index op_slots = static_cast<Eigen::Index>(global_slot.size());
  TetMesh& view = operational_view_;
  view.rest = mesh.rest;
  view.x.resize(0, 3);
  view.v.resize(0, 3);
  view.tets.conservativeResize(op_slots, 4);
  view.labels.conservativeResize(op_slots);
  std::vector<char> op_alive(static_cast<std::size_t>(op_slots), 0);
  for (Eigen::Index k = 0; k < op_slots; ++k)
    op_alive[static_cast<std::size_t>(k)] = alive[static_cast<std::size_t>(global_slot[k])];
  std::vector<int> op_changed;
  op_changed.reserve(changed.size() + (slots - old_slots));
  for (const int s : changed) {
    const int k = operational_slot[static_cast<std::size_t>(s)];
    op_changed.push_back(k);
    view.tets.row(k) = mesh.tets.row(s);
    view.labels(k) = mesh.labels.size() == 0 ? 0 : mesh.labels(s);
  }
  for (std::size_t t = old_slots; t < slots; ++t) {
    const int k = operational_slot[t];
    if (std::find(op_changed.begin(), op_changed.end(), k) == op_changed.end()) {
      op_changed.push_back(k);  // a new slot is a change even if the caller did not list it
      view.tets.row(k) = mesh.tets.row(static_cast<Eigen::Index>(t));
      view.labels(k) = mesh.labels.size() == 0 ? 0 : mesh.labels(static_cast<Eigen::Index>(t));
    }
  }
  operational_->update_elements(view, op_alive, op_changed);

  slot_operational_.resize(slots, 1);
  operational_slot_ = std::move(operational_slot);
  global_slot_ = std::move(global_slot);
  rebuild_masses();
  topology_changed();
}

bool HybridCondensedModel::soften_element(int t, Real factor) {
  if (t < 0 || static_cast<std::size_t>(t) >= slot_operational_.size()) {
    throw std::invalid_argument(where("soften_element: slot ") + std::to_string(t) +
                                " is out of range");
  }
  if (slot_operational_[static_cast<std::size_t>(t)] == 0) return false;
  return operational_->soften_element(operational_slot_[static_cast<std::size_t>(t)], factor);
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
  const VecX u_i = -interior_solver_.solve(VecX(k_is_ * u_s));
  for (std::size_t k = 0; k < interior_.size(); ++k) {
    const int i = interior_[k];
    x.row(i) = rest_.row(i) + u_i.segment<3>(3 * static_cast<Eigen::Index>(k)).transpose();
  }
}

}  // namespace incise::sim
