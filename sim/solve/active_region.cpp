#include "sim/solve/active_region.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace incise::sim {

namespace {

void check_settings(const ActiveRegionSettings& s) {
  if (!(s.sleep_speed >= 0) || !(s.sleep_force >= 0)) {
    throw std::invalid_argument("active region: sleep_speed and sleep_force must be >= 0");
  }
  if (!(s.wake_force > s.sleep_force)) {
    throw std::invalid_argument("active region: wake_force (" + std::to_string(s.wake_force) +
                                ") must exceed sleep_force (" + std::to_string(s.sleep_force) +
                                "), or nodes near the threshold flicker");
  }
  if (s.sleep_frames < 1) {
    throw std::invalid_argument("active region: sleep_frames must be >= 1");
  }
}

}  // namespace

ActiveRegion::ActiveRegion(const Tets& tets, int num_nodes, const ActiveRegionSettings& settings)
    : tets_(tets),
      settings_(settings),
      state_(static_cast<std::size_t>(num_nodes), kAsleep),
      calm_frames_(static_cast<std::size_t>(num_nodes), 0),
      mark_(static_cast<std::size_t>(num_nodes), 0) {
  check_settings(settings);
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    for (int k = 0; k < 4; ++k) {
      if (tets(t, k) < 0 || tets(t, k) >= num_nodes) {
        throw std::invalid_argument("active region: tet " + std::to_string(t) + " refers to node " +
                                    std::to_string(tets(t, k)) + " outside [0, " +
                                    std::to_string(num_nodes) + ")");
      }
    }
  }
}

bool ActiveRegion::wake(int node) {
  if (state_[node] != kAsleep) return false;
  state_[node] = kActive;
  calm_frames_[node] = 0;
  changed_ = true;
  return true;
}

void ActiveRegion::fix(int node) {
  if (state_[node] == kFixed) return;
  state_[node] = kFixed;
  changed_ = true;
}

bool ActiveRegion::observe(int node, Real speed, Real net_force) {
  if (state_[node] != kActive) return false;
  const bool calm = speed < settings_.sleep_speed && net_force < settings_.sleep_force;
  calm_frames_[node] = calm ? calm_frames_[node] + 1 : 0;
  if (calm_frames_[node] < settings_.sleep_frames) return false;
  state_[node] = kAsleep;
  calm_frames_[node] = 0;
  changed_ = true;
  return true;
}

void ActiveRegion::update_sets() {
  active_nodes_.clear();
  active_tets_.clear();
  evaluated_tets_.clear();
  complete_nodes_.clear();
  const int n = num_nodes();
  for (int i = 0; i < n; ++i) {
    mark_[i] = 0;
    if (state_[i] == kActive) active_nodes_.push_back(i);
  }
  // mark_ = 1 on the nodes of active tets (active and frontier nodes).
  for (Eigen::Index t = 0; t < tets_.rows(); ++t) {
    bool active = false;
    for (int k = 0; k < 4; ++k)
      active = active || state_[tets_(t, k)] == kActive;
    if (!active) continue;
    active_tets_.push_back(static_cast<int>(t));
    for (int k = 0; k < 4; ++k)
      mark_[tets_(t, k)] = 1;
  }
  for (int i = 0; i < n; ++i) {
    if (mark_[i] != 0) complete_nodes_.push_back(i);
  }
  for (Eigen::Index t = 0; t < tets_.rows(); ++t) {
    bool evaluated = false;
    for (int k = 0; k < 4; ++k)
      evaluated = evaluated || mark_[tets_(t, k)] != 0;
    if (evaluated) evaluated_tets_.push_back(static_cast<int>(t));
  }
  changed_ = false;
}

ActiveExplicitStepper::ActiveExplicitStepper(const TetMesh& mesh, ModelFactory factory,
                                             const ActiveRegionSettings& settings,
                                             const std::vector<int>& fixed)
    : mesh_(mesh),
      factory_(std::move(factory)),
      region_(mesh.tets, mesh.num_nodes(), settings),
      held_force_(Points::Zero(mesh.num_nodes(), 3)),
      in_sub_(static_cast<std::size_t>(mesh.num_tets()), 0),
      sub_f_(mesh.num_nodes(), 3) {
  if (mesh_.labels.size() != mesh_.tets.rows())
    mesh_.labels = Eigen::VectorXi::Zero(mesh.tets.rows());
  // The whole model once: the masses and the forces every node starts with. Then all its
  // elements are dropped (Model::update_elements); the evaluated tets come back as they wake.
  sub_model_ = factory_(mesh_);
  masses_ = sub_model_->masses();
  sub_model_->add_forces(mesh.x, mesh.v, held_force_);
  std::vector<int> all(static_cast<std::size_t>(mesh.num_tets()));
  for (int t = 0; t < mesh.num_tets(); ++t)
    all[static_cast<std::size_t>(t)] = t;
  sub_model_->update_elements(mesh_, in_sub_, all);
  for (const int node : fixed) {
    if (node < 0 || node >= mesh.num_nodes()) {
      throw std::invalid_argument("active region: fixed node " + std::to_string(node) +
                                  " outside [0, " + std::to_string(mesh.num_nodes()) + ")");
    }
    region_.fix(node);
  }
  // A node without a tet has no mass to integrate: it is held like a fixed one. A node that
  // starts moving is awake (sleeping nodes have v = 0, which the exactness argument needs).
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (!(masses_(i) > 0)) region_.fix(i);
    if (mesh.v.row(i).squaredNorm() > 0) region_.wake(i);
  }
}

void ActiveExplicitStepper::update_region() {
  region_.update_sets();
  const std::vector<int>& needed = region_.evaluated_tets();
  changed_.clear();
  for (const int t : needed) {
    if (in_sub_[static_cast<std::size_t>(t)] == 0) changed_.push_back(t);
  }
  // A sub-model larger than needed still gives the exact forces (the argument above needs only
  // that it holds the needed tets), so it keeps the tets of a region falling asleep until it is
  // twice the size needed: the nodes of a decaying wave fall asleep one by one, and an update per
  // sleep would cost more than evaluating the sleepers' tets.
  const std::size_t size_after = sub_count_ + changed_.size();
  const bool shrink = size_after > 2 * needed.size();
  if (changed_.empty() && !shrink) return;
  for (const int t : changed_)
    in_sub_[static_cast<std::size_t>(t)] = 1;
  if (shrink) {
    // Everything in the sub-model that is not needed leaves it.
    std::vector<char> keep(in_sub_.size(), 0);
    for (const int t : needed)
      keep[static_cast<std::size_t>(t)] = 1;
    for (std::size_t t = 0; t < in_sub_.size(); ++t) {
      if (in_sub_[t] != 0 && keep[t] == 0) {
        in_sub_[t] = 0;
        changed_.push_back(static_cast<int>(t));
      }
    }
  }
  sub_count_ = static_cast<std::size_t>(std::count(in_sub_.begin(), in_sub_.end(), 1));
  metrics_.rebuilt = true;
  sub_model_->update_elements(mesh_, in_sub_, changed_);
  ++rebuilds_;
}

void ActiveExplicitStepper::evaluate_forces(const Points& x, const Points& v) {
  if (sub_count_ == 0) return;
  sub_f_.setZero();
  sub_model_->add_forces(x, v, sub_f_);
  for (const int node : region_.complete_nodes())
    held_force_.row(node) = sub_f_.row(node);
}

Real ActiveExplicitStepper::net_force(int node, const Vec3& gravity, const Points& external) const {
  return (row3(held_force_, node) + row3(external, node) + masses_(node) * gravity).norm();
}

void ActiveExplicitStepper::step(Real dt, const Vec3& gravity, const Points& external, Points& x,
                                 Points& v) {
  metrics_.wakes = 0;
  metrics_.sleeps = 0;
  metrics_.rebuilt = false;
  if (region_.changed()) update_region();
  evaluate_forces(x, v);

  // Only nodes that are asleep can wake; their held forces are current on the frontier and
  // constant deeper in (every tet there is frozen).
  const int n = region_.num_nodes();
  for (int i = 0; i < n; ++i) {
    if (region_.node_active(i) || region_.node_fixed(i)) continue;
    if (region_.should_wake(net_force(i, gravity, external)) && region_.wake(i)) {
      ++metrics_.wakes;
    }
  }
  if (metrics_.wakes > 0) {
    update_region();
    evaluate_forces(x, v);
  }

  for (const int i : region_.active_nodes()) {
    const Vec3 f = row3(held_force_, i) + row3(external, i) + masses_(i) * gravity;
    const Vec3 vi = row3(v, i) + dt * f / masses_(i);
    v.row(i) = vi.transpose();
    x.row(i) += dt * vi.transpose();
    if (region_.observe(i, vi.norm(), f.norm())) {
      v.row(i).setZero();
      ++metrics_.sleeps;
    }
  }
  metrics_.active_nodes = static_cast<int>(region_.active_nodes().size());
  metrics_.active_tets = static_cast<int>(region_.active_tets().size());
  metrics_.evaluated_tets = static_cast<int>(sub_count_);
}

}  // namespace incise::sim
