#include "sim/remesh/adaptive_body.h"

#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/remesh/flips.h"
#include "sim/remesh/state_transfer.h"

namespace incise::sim::remesh {

namespace {

RemeshMesh constrained_delaunay(const TetMesh& mesh) {
  RemeshMesh remesh(mesh);
  make_constrained_delaunay(remesh);
  return remesh;
}

}  // namespace

AdaptiveBody::AdaptiveBody(const TetMesh& mesh, const ModelFactory& make_model)
    : mesh_(constrained_delaunay(mesh)) {
  if (!make_model) throw std::invalid_argument("AdaptiveBody: no model factory");
  const int n = mesh.num_nodes();
  for (int i = 0; i < n; ++i) {
    // The model's node i must be vertex slot i, so every node must stay a vertex.
    if (!mesh_.vertex_alive(i)) {
      throw std::invalid_argument("AdaptiveBody: node " + std::to_string(i) + " belongs to no tet");
    }
  }
  const bool has_x = mesh.x.rows() == n;
  const bool has_v = mesh.v.rows() == n;
  if ((mesh.x.rows() != 0 && !has_x) || (mesh.v.rows() != 0 && !has_v)) {
    throw std::invalid_argument("AdaptiveBody: x and v need one row per node (or none)");
  }
  view_.rest = mesh.rest;
  view_.x = has_x ? mesh.x : mesh.rest;
  view_.v = has_v ? mesh.v : Points::Zero(n, 3);
  view_.tets = Tets::Zero(0, 4);
  view_.labels.resize(0);

  // The model is made on the compact mesh, whose tet r is the r-th alive slot; the flips of
  // make_constrained_delaunay may have left free slots, in which case one update over every
  // slot moves the model onto the slot view.
  TetMesh compact = mesh_.to_tet_mesh();
  compact.x = view_.x;
  compact.v = view_.v;
  model_ = make_model(compact);
  if (!model_) throw std::invalid_argument("AdaptiveBody: the factory made no model");
  const int slots = mesh_.num_tet_slots();
  changed_mark_.assign(static_cast<std::size_t>(slots), 0);
  changed_.clear();
  if (slots != mesh_.num_tets()) {
    changed_.resize(static_cast<std::size_t>(slots));
    std::iota(changed_.begin(), changed_.end(), 0);
    commit_changes();
  } else {
    view_.tets.resize(slots, 4);
    view_.labels.resize(slots);
    alive_.assign(static_cast<std::size_t>(slots), 1);
    for (int t = 0; t < slots; ++t) {
      for (int k = 0; k < 4; ++k)
        view_.tets(t, k) = mesh_.tet(t)[static_cast<std::size_t>(k)];
      view_.labels(t) = mesh_.label(t);
    }
  }
  fixed_.assign(static_cast<std::size_t>(n), 0);
  forces_ = Points::Zero(n, 3);
  update_inverse_masses();
}

void AdaptiveBody::set_fixed(FixedPredicate is_fixed) {
  is_fixed_ = std::move(is_fixed);
  for (int i = 0; i < num_vertex_slots(); ++i) {
    fixed_[static_cast<std::size_t>(i)] =
        is_fixed_ && mesh_.vertex_alive(i) && is_fixed_(mesh_.point(i)) ? 1 : 0;
  }
  update_inverse_masses();
}

RemeshListener AdaptiveBody::listener() {
  RemeshListener listener;
  listener.on_inserted = [this](const InsertedVertex& inserted, const TetChanges& changes) {
    grow_vertex_slots();
    const int s = inserted.vertex;
    const std::size_t ss = static_cast<std::size_t>(s);
    view_.rest.row(s) = inserted.rest_point.transpose();
    // Paloc 2006, Figure 4: the new node sits at the same barycentric point of the deformed host
    // tet and moves with the host's interpolated velocity, so nothing else moves.
    view_.x.row(s) = interpolate_rows(view_.x, inserted.host, inserted.weights).transpose();
    view_.v.row(s) = interpolate_rows(view_.v, inserted.host, inserted.weights).transpose();
    fixed_[ss] = is_fixed_ && is_fixed_(inserted.rest_point) ? 1 : 0;
    record(changes);
  };
  listener.on_removal = [this](int vertex, const RemoveResult& removal) {
    record(removal.changes);
    if (removal.status != RemoveStatus::kRemoved) return;
    // A dead slot stays at a finite place and never moves (no mass, no velocity).
    view_.x.row(vertex) = view_.rest.row(vertex);
    view_.v.row(vertex).setZero();
    fixed_[static_cast<std::size_t>(vertex)] = 0;
  };
  return listener;
}

void AdaptiveBody::grow_vertex_slots() {
  const Eigen::Index old = view_.rest.rows();
  const Eigen::Index n = mesh_.num_vertex_slots();
  if (n <= old) return;
  view_.rest.conservativeResize(n, 3);
  view_.x.conservativeResize(n, 3);
  view_.v.conservativeResize(n, 3);
  for (Eigen::Index i = old; i < n; ++i) {
    view_.rest.row(i) = mesh_.point(static_cast<int>(i)).transpose();
    view_.x.row(i) = view_.rest.row(i);
    view_.v.row(i).setZero();
  }
  fixed_.resize(static_cast<std::size_t>(n), 0);
}

void AdaptiveBody::record(const TetChanges& changes) {
  for (const auto* ids : {&changes.removed, &changes.created}) {
    for (const int t : *ids) {
      const std::size_t ts = static_cast<std::size_t>(t);
      if (ts >= changed_mark_.size()) changed_mark_.resize(ts + 1, 0);
      if (changed_mark_[ts] != 0) continue;
      changed_mark_[ts] = 1;
      changed_.push_back(t);
    }
  }
}

void AdaptiveBody::commit_changes() {
  grow_vertex_slots();
  const int slots = mesh_.num_tet_slots();
  const Eigen::Index old = view_.tets.rows();
  if (slots > old) {
    view_.tets.conservativeResize(slots, 4);
    view_.labels.conservativeResize(slots);
    view_.tets.bottomRows(slots - old).setZero();
    view_.labels.tail(slots - old).setZero();
    alive_.resize(static_cast<std::size_t>(slots), 0);
  }
  touched_mark_.resize(static_cast<std::size_t>(num_vertex_slots()), 0);
  const auto touch = [this](int vertex) {
    const std::size_t vs = static_cast<std::size_t>(vertex);
    if (touched_mark_[vs] != 0) return;
    touched_mark_[vs] = 1;
    touched_vertices_.push_back(vertex);
  };
  for (const int t : changed_) {
    // The slot's previous tet (if it was alive) lost its share of its vertices' masses.
    if (alive_[static_cast<std::size_t>(t)] != 0) {
      for (int k = 0; k < 4; ++k)
        touch(view_.tets(t, k));
    }
    const bool alive = mesh_.tet_alive(t);
    alive_[static_cast<std::size_t>(t)] = alive ? 1 : 0;
    if (!alive) continue;
    for (int k = 0; k < 4; ++k) {
      view_.tets(t, k) = mesh_.tet(t)[static_cast<std::size_t>(k)];
      touch(view_.tets(t, k));
    }
    view_.labels(t) = mesh_.label(t);
  }
  if (!changed_.empty()) model_->update_elements(view_, alive_, changed_);
  for (const int t : changed_)
    changed_mark_[static_cast<std::size_t>(t)] = 0;
  changed_.clear();
  // New slots start without mass; those in a tet are among the touched vertices.
  const Eigen::Index before = inv_mass_.size();
  if (before < num_vertex_slots()) {
    inv_mass_.conservativeResize(num_vertex_slots());
    inv_mass_.tail(num_vertex_slots() - before).setZero();
  }
  for (const int vertex : touched_vertices_)
    update_inverse_mass(vertex);
  for (const int vertex : touched_vertices_)
    touched_mark_[static_cast<std::size_t>(vertex)] = 0;
  touched_vertices_.clear();
}

void AdaptiveBody::update_inverse_masses() {
  inv_mass_.resize(num_vertex_slots());
  for (int i = 0; i < num_vertex_slots(); ++i)
    update_inverse_mass(i);
}

void AdaptiveBody::update_inverse_mass(int i) {
  const VecX& masses = model_->masses();
  const Real m = i < masses.size() ? masses(i) : 0;
  const bool moves = fixed_[static_cast<std::size_t>(i)] == 0 && mesh_.vertex_alive(i) && m > 0;
  inv_mass_(i) = moves ? 1 / m : 0;
  // symplectic_euler_step still advances x by v where the inverse mass is 0.
  if (!moves) view_.v.row(i).setZero();
}

RefinementStats AdaptiveBody::refine(const SizeField& target_size,
                                     const RefinementSettings& settings) {
  RefinementStats stats;
  try {
    stats = remesh::refine(mesh_, target_size, settings, listener());
  } catch (...) {
    // Keep the model in step with whatever edits were made before the failure.
    commit_changes();
    throw;
  }
  commit_changes();
  return stats;
}

DecimationStats AdaptiveBody::decimate(const SizeField& keep_refined, int max_attempts) {
  if (max_attempts < 0) throw std::invalid_argument("AdaptiveBody::decimate: max_attempts < 0");
  decimator_.collect(mesh_, keep_refined);
  const DecimationStats stats = decimator_.step(mesh_, keep_refined, max_attempts, listener());
  commit_changes();
  return stats;
}

void AdaptiveBody::internal_forces(Points& f) {
  f.setZero(num_vertex_slots(), 3);
  model_->add_forces(view_.x, view_.v, f);
}

void AdaptiveBody::step(Real dt, const Vec3& gravity, const Points& external) {
  if (!(dt > 0)) throw std::invalid_argument("AdaptiveBody::step: dt must be > 0");
  const int n = num_vertex_slots();
  if (external.rows() != 0 && external.rows() != n) {
    throw std::invalid_argument("AdaptiveBody::step: external has " +
                                std::to_string(external.rows()) + " rows for " + std::to_string(n) +
                                " vertex slots");
  }
  if (forces_.rows() != n) forces_.resize(n, 3);
  forces_.setZero();
  model_->add_forces(view_.x, view_.v, forces_);
  if (external.rows() != 0) forces_ += external;
  symplectic_euler_step(dt, gravity, inv_mass_, none_, forces_, view_.x, view_.v);
}

TetMesh AdaptiveBody::to_tet_mesh(std::vector<int>* vertex_ids) const {
  std::vector<int> local;
  std::vector<int>& ids = vertex_ids != nullptr ? *vertex_ids : local;
  TetMesh out = mesh_.to_tet_mesh(&ids);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const Eigen::Index row = static_cast<Eigen::Index>(i);
    out.x.row(row) = view_.x.row(ids[i]);
    out.v.row(row) = view_.v.row(ids[i]);
  }
  return out;
}

}  // namespace incise::sim::remesh
