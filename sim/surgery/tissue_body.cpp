#include "sim/surgery/tissue_body.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/collide/mesh_surface_faces.h"
#include "sim/models/rotation_extraction.h"
#include "sim/solve/stable_time_step.h"

namespace incise::sim::surgery {

namespace {

std::array<Real, 3> key_of(const Points& rest, int node) {
  return {rest(node, 0), rest(node, 1), rest(node, 2)};
}

}  // namespace

TissueBody::TissueBody(TetMesh mesh, const ModelFactory& make_model, std::vector<char> fixed,
                       Real dt, Real wave_speed, Real damping_time, std::vector<char> far_field)
    : mesh_(std::move(mesh)),
      fixed_(std::move(fixed)),
      far_(std::move(far_field)),
      dt_(dt),
      wave_speed_(wave_speed),
      damping_time_(damping_time) {
  if (mesh_.num_tets() == 0) throw std::invalid_argument("tissue: the mesh has no tetrahedra");
  if (!(dt_ > 0 && std::isfinite(dt_))) throw std::invalid_argument("tissue: dt must be > 0");
  if (!(wave_speed_ > 0 && std::isfinite(wave_speed_))) {
    throw std::invalid_argument("tissue: wave_speed must be > 0");
  }
  if (!(damping_time_ >= 0 && std::isfinite(damping_time_))) {
    throw std::invalid_argument("tissue: damping_time must be >= 0");
  }
  if (static_cast<int>(fixed_.size()) != mesh_.num_nodes()) {
    throw std::invalid_argument("tissue: fixed has " + std::to_string(fixed_.size()) +
                                " entries for " + std::to_string(mesh_.num_nodes()) + " nodes");
  }
  if (!make_model) throw std::invalid_argument("tissue: no model factory");
  if (mesh_.x.rows() != mesh_.rest.rows()) mesh_.x = mesh_.rest;
  if (mesh_.v.rows() != mesh_.rest.rows()) mesh_.v = Points::Zero(mesh_.rest.rows(), 3);
  if (!far_.empty() && static_cast<int>(far_.size()) != mesh_.num_tets()) {
    throw std::invalid_argument("tissue: far_field has " + std::to_string(far_.size()) +
                                " entries for " + std::to_string(mesh_.num_tets()) + " tets");
  }
  model_ = make_model(mesh_);
  if (!model_) throw std::invalid_argument("tissue: the model factory made no model");
  if (!far_.empty()) {
    condensed_ = dynamic_cast<HybridCondensedModel*>(model_.get());
    if (condensed_ == nullptr) {
      throw std::invalid_argument("tissue: a far field needs the hybrid condensed model");
    }
    pinned_.assign(static_cast<std::size_t>(mesh_.num_nodes()), 0);
    for (int t = 0; t < mesh_.num_tets(); ++t) {
      if (far_[static_cast<std::size_t>(t)] == 0) continue;
      for (int k = 0; k < 4; ++k)
        pinned_[static_cast<std::size_t>(mesh_.tets(t, k))] = 1;
    }
  }
  for (int i = 0; i < mesh_.num_nodes(); ++i) {
    if (fixed_[static_cast<std::size_t>(i)] != 0) fixed_rest_.push_back(key_of(mesh_.rest, i));
  }
  std::sort(fixed_rest_.begin(), fixed_rest_.end());
  update_inverse_masses();
  rebuild_surface();
  internal_ = forces_ = Points::Zero(mesh_.num_nodes(), 3);
}

std::unique_ptr<TissueBody> TissueBody::clone() const {
  auto copy = std::unique_ptr<TissueBody>(new TissueBody(*this));
  // recover_inverted's scratch is no state: a checkpoint does not carry it.
  copy->recover_part_ = {};
  copy->recover_fit_ = {};
  copy->condensed_ =
      condensed_ != nullptr ? dynamic_cast<HybridCondensedModel*>(copy->model_.get()) : nullptr;
  return copy;
}

void TissueBody::rebuild_surface(std::span<const int>* changed) {
  bool local = changed != nullptr;
  if (local) {
    try {
      boundary_.update(mesh_.tets, *changed);
    } catch (const std::invalid_argument&) {
      local = false;  // the tracker is half updated: from scratch (which throws as it did)
    }
  }
  if (!local) boundary_ = BoundaryTracker(mesh_.tets);
  surface_ = boundary_.surface(mesh_.num_nodes());
  faces_ = collide::mesh_surface_faces(surface_);
  bvh_.build(mesh_.x, faces_);
}

void TissueBody::update_inverse_masses() {
  // The stability guard (see the constructor): per node, the largest scale over its tets.
  mass_scale_.assign(static_cast<std::size_t>(mesh_.num_nodes()), 1);
  softened_elements_ = 0;
  min_stiffness_factor_ = 1;
  const Real need = dt_ * dt_ + 2 * damping_time_ * dt_;  // dt_e^2 an element must reach
  for (int t = 0; t < mesh_.num_tets(); ++t) {
    const Vec3 a = row3(mesh_.rest, mesh_.tets(t, 0)), b = row3(mesh_.rest, mesh_.tets(t, 1)),
               c = row3(mesh_.rest, mesh_.tets(t, 2)), d = row3(mesh_.rest, mesh_.tets(t, 3));
    // Smallest altitude: 3 V / the largest face area.
    const Real volume = std::abs(signed_volume(a, b, c, d));
    const Real face = 0.5 * std::max({(b - a).cross(c - a).norm(), (b - a).cross(d - a).norm(),
                                      (c - a).cross(d - a).norm(), (c - b).cross(d - b).norm()});
    const Real step = kExplicitSafety * (face > 0 ? 3 * volume / face : 0) / wave_speed_;
    if (step * step >= need) continue;
    const Real scale = step > 0 ? std::min(need / (step * step), Real(1e12)) : Real(1e12);
    // Softening the sliver lowers its w^2 as much without making its nodes heavy: heavy nodes
    // carry the inertia of thousands of others and distort the whole organ's motion.
    if (model_->soften_element(t, 1 / scale)) {
      ++softened_elements_;
      min_stiffness_factor_ = std::min(min_stiffness_factor_, 1 / scale);
      continue;
    }
    for (int k = 0; k < 4; ++k) {
      Real& s = mass_scale_[static_cast<std::size_t>(mesh_.tets(t, k))];
      s = std::max(s, scale);
    }
  }
  const VecX& m = model_->masses();
  inv_mass_.resize(mesh_.num_nodes());
  mass_scaled_nodes_ = 0;
  max_mass_scale_ = 1;
  for (int i = 0; i < mesh_.num_nodes(); ++i) {
    const std::size_t is = static_cast<std::size_t>(i);
    const bool moves = fixed_[is] == 0 && i < m.size() && m(i) > 0;
    inv_mass_(i) = moves ? 1 / (m(i) * mass_scale_[is]) : 0;
    if (!moves) mesh_.v.row(i).setZero();
    if (moves && mass_scale_[is] > 1) {
      ++mass_scaled_nodes_;
      max_mass_scale_ = std::max(max_mass_scale_, mass_scale_[is]);
    }
  }
}

void TissueBody::begin_step() {
  if (bvh_.needs_rebuild()) {
    bvh_.rebuild(mesh_.x);
  } else {
    bvh_.refit(mesh_.x);
  }
  internal_.setZero();
  model_->add_forces(mesh_.x, mesh_.v, internal_);
  forces_ = internal_;
}

void TissueBody::set_ambient_damping(Real per_second) {
  if (!(per_second >= 0 && std::isfinite(per_second))) {
    throw std::invalid_argument("tissue: ambient damping must be >= 0");
  }
  ambient_damping_ = per_second;
}

void TissueBody::end_step(Real dt, const Vec3& gravity, const Prescribed& prescribed) {
  if (ambient_damping_ > 0) mesh_.v /= 1 + ambient_damping_ * dt;
  symplectic_euler_step(dt, gravity, inv_mass_, prescribed, forces_, mesh_.x, mesh_.v);
}

namespace {
Real distance_to_segment(const Vec3& p, const TissueBody::Segment& s) {
  const Vec3 ab = s.b - s.a;
  const Real length2 = ab.squaredNorm();
  const Real t = length2 > 0 ? std::clamp((p - s.a).dot(ab) / length2, Real(0), Real(1)) : 0;
  return (p - (s.a + t * ab)).norm();
}
}  // namespace

int TissueBody::recover_inverted(Real fraction, std::span<const Segment> clear_of,
                                 const AxisMask* held) {
  const int nodes = mesh_.num_nodes();
  const int tets = mesh_.num_tets();
  // The tangles: inverted tets clear of the tools, joined into parts by shared nodes (a union-
  // find over the nodes; -1: in no such tet).
  std::vector<int>& part = recover_part_;
  part.assign(static_cast<std::size_t>(nodes), -1);
  const auto root = [&part](int node) {
    while (part[static_cast<std::size_t>(node)] != node) {
      int& up = part[static_cast<std::size_t>(node)];
      up = part[static_cast<std::size_t>(up)];  // path halving
      node = up;
    }
    return node;
  };
  int pulled = 0;
  for (int t = 0; t < tets; ++t) {
    if (!far_.empty() && far_[static_cast<std::size_t>(t)] != 0) continue;
    const auto tet = mesh_.tets.row(t);
    Mat3 ds;
    for (int k = 0; k < 3; ++k)
      ds.col(k) = (mesh_.x.row(tet(k + 1)) - mesh_.x.row(tet(0))).transpose();
    // Rest tets are positively oriented (TetMesh): the sign of det Ds is det F's.
    if (ds.determinant() > 0) continue;
    bool near_tool = false;
    for (int k = 0; k < 4 && !near_tool; ++k) {
      for (const Segment& segment : clear_of) {
        near_tool = near_tool ||
                    distance_to_segment(mesh_.x.row(tet(k)).transpose(), segment) < segment.radius;
      }
    }
    if (near_tool) continue;
    for (int k = 0; k < 4; ++k) {
      const int node = tet(k);
      if (part[static_cast<std::size_t>(node)] < 0) part[static_cast<std::size_t>(node)] = node;
    }
    for (int k = 1; k < 4; ++k) {
      const int a = root(tet(0));
      const int b = root(tet(k));
      if (a != b) part[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
    ++pulled;
  }
  if (pulled == 0) return 0;
  // Each part's rigid fit to its rest shape (mass-weighted): the rotation nearest to
  // A = sum m (x - c)(X - C)^T, the part then pulled toward c + R (X - C). Nodes that cannot
  // move (held, the far field's) weigh a million times their mass: where a part has them, the
  // fit is theirs, so that the free nodes are pulled to a shape that agrees with them.
  const auto immovable = [this, held](int node) {
    return inv_mass_(node) == 0 || far_field_node(node) ||
           (held != nullptr && held->rows() == mesh_.num_nodes() && held->row(node).any());
  };
  const auto weight = [this, &immovable](int node) {
    return masses()(node) * (immovable(node) ? 1e6 : 1);
  };
  recover_fit_.assign(static_cast<std::size_t>(nodes), PartFit{});
  for (int node = 0; node < nodes; ++node) {
    if (part[static_cast<std::size_t>(node)] < 0) continue;
    PartFit& fit = recover_fit_[static_cast<std::size_t>(root(node))];
    const Real m = weight(node);
    fit.mass += m;
    fit.centre += m * mesh_.x.row(node).transpose();
    fit.rest_centre += m * mesh_.rest.row(node).transpose();
  }
  for (int node = 0; node < nodes; ++node) {
    if (part[static_cast<std::size_t>(node)] != node) continue;
    PartFit& fit = recover_fit_[static_cast<std::size_t>(node)];
    if (!(fit.mass > 0)) continue;  // massless nodes only: never pulled (below)
    fit.centre /= fit.mass;
    fit.rest_centre /= fit.mass;
  }
  for (int node = 0; node < nodes; ++node) {
    if (part[static_cast<std::size_t>(node)] < 0) continue;
    PartFit& fit = recover_fit_[static_cast<std::size_t>(root(node))];
    fit.covariance += weight(node) * (mesh_.x.row(node).transpose() - fit.centre) *
                      (mesh_.rest.row(node) - fit.rest_centre.transpose());
  }
  for (int node = 0; node < nodes; ++node) {
    if (part[static_cast<std::size_t>(node)] == node) {
      PartFit& fit = recover_fit_[static_cast<std::size_t>(node)];
      // Scaled to a unit norm (the rotation of a positive multiple is the same): polar_rotation
      // is written for deformation gradients, of order 1, and its tolerances are absolute.
      const Real norm = fit.covariance.norm();
      if (fit.mass > 0 && norm > 0) fit.rotation = polar_rotation(fit.covariance / norm);
    }
  }
  for (int node = 0; node < nodes; ++node) {
    if (part[static_cast<std::size_t>(node)] < 0 || immovable(node)) continue;
    const PartFit& fit = recover_fit_[static_cast<std::size_t>(root(node))];
    if (!(fit.mass > 0)) continue;
    const Vec3 target =
        fit.centre + fit.rotation * (mesh_.rest.row(node).transpose() - fit.rest_centre);
    mesh_.x.row(node) += fraction * (target - mesh_.x.row(node).transpose()).transpose();
    mesh_.v.row(node).setZero();
  }
  return pulled;
}

cut::SimplifyReport TissueBody::simplify(std::span<const int> region,
                                         const cut::SimplifyOptions& options) {
  cut::SimplifyReport report = cut::simplify_cut_region(mesh_, region, options, pinned_);
  if (report.collapses > 0) after_compaction(report.node_map, report.tet_map);
  return report;
}

void TissueBody::recover_far_field() {
  if (condensed_ != nullptr) condensed_->recover_interior(mesh_.x);
}

void TissueBody::grow_far_field() {
  if (far_.empty()) return;
  far_.resize(static_cast<std::size_t>(mesh_.num_tets()), 0);
  pinned_.resize(static_cast<std::size_t>(mesh_.num_nodes()), 0);
}

void TissueBody::after_compaction(std::span<const int> node_map, std::span<const int> tet_map) {
  if (!far_.empty()) {
    // Far-field tets and nodes are never removed; the order is kept.
    std::vector<char> far(static_cast<std::size_t>(mesh_.num_tets()), 0);
    for (std::size_t t = 0; t < tet_map.size() && t < far_.size(); ++t) {
      if (tet_map[t] >= 0) far[static_cast<std::size_t>(tet_map[t])] = far_[t];
    }
    far_ = std::move(far);
    std::vector<char> pinned(static_cast<std::size_t>(mesh_.num_nodes()), 0);
    for (std::size_t i = 0; i < node_map.size() && i < pinned_.size(); ++i) {
      if (node_map[i] >= 0) pinned[static_cast<std::size_t>(node_map[i])] = pinned_[i];
    }
    pinned_ = std::move(pinned);
  }
  std::vector<char> fixed(static_cast<std::size_t>(mesh_.num_nodes()), 0);
  for (std::size_t i = 0; i < node_map.size(); ++i) {
    const int to = node_map[i];
    if (to >= 0) fixed[static_cast<std::size_t>(to)] = fixed_[i];
  }
  fixed_ = std::move(fixed);
  remap_bisections(bisections_, node_map);
  model_->update_topology(mesh_);
  ++full_updates_;
  update_inverse_masses();
  rebuild_surface();
  internal_.setZero(mesh_.num_nodes(), 3);
  forces_.setZero(mesh_.num_nodes(), 3);
}

Real TissueBody::altitude_floor() const {
  return wave_speed_ * std::sqrt(dt_ * dt_ + 2 * damping_time_ * dt_) / kExplicitSafety;
}

BisectionReport TissueBody::refine(const Vec3& centre, Real radius, Real edge_length,
                                   int max_splits) {
  BisectionSettings settings;
  settings.edge_length = edge_length;
  settings.max_splits = max_splits;
  // A little above the floor: the guard compares squares of a computed step.
  settings.min_altitude = 1.01 * altitude_floor();
  BisectionReport report = refine_ball(mesh_, centre, radius, settings, far_);
  grow_far_field();
  if (report.splits == 0) return report;
  fixed_.resize(static_cast<std::size_t>(mesh_.num_nodes()), 0);
  bool held_added = false;
  for (const Bisection& s : report.bisections) {
    const bool held =
        fixed_[static_cast<std::size_t>(s.a)] != 0 && fixed_[static_cast<std::size_t>(s.b)] != 0;
    fixed_[static_cast<std::size_t>(s.mid)] = held ? 1 : 0;
    // A cut's copy of a held new node is held too (topology_changed looks it up by rest point).
    if (held) {
      fixed_rest_.push_back(key_of(mesh_.rest, s.mid));
      held_added = true;
    }
  }
  if (held_added) std::sort(fixed_rest_.begin(), fixed_rest_.end());
  bisections_.insert(bisections_.end(), report.bisections.begin(), report.bisections.end());
  alive_.assign(static_cast<std::size_t>(mesh_.num_tets()), 1);
  model_->update_elements(mesh_, alive_, report.changed);
  ++local_updates_;
  update_inverse_masses();
  std::span<const int> split(report.changed);
  rebuild_surface(&split);
  internal_.setZero(mesh_.num_nodes(), 3);
  forces_.setZero(mesh_.num_nodes(), 3);
  return report;
}

CoarsenReport TissueBody::coarsen(const std::function<bool(const Vec3& rest)>& keep) {
  CoarsenReport report = undo_bisections(mesh_, bisections_, keep);
  if (report.undone == 0) return report;
  // undo_bisections renumbered the remaining splits already; the held flags follow here.
  std::vector<Bisection> kept;
  kept.swap(bisections_);
  after_compaction(report.node_map, report.tet_map);
  bisections_ = std::move(kept);
  return report;
}

void TissueBody::topology_changed(int tets_before, std::span<const int> changed) {
  const int n = mesh_.num_nodes();
  grow_far_field();
  const std::size_t old_nodes = fixed_.size();
  fixed_.resize(static_cast<std::size_t>(n), 0);
  for (std::size_t i = old_nodes; i < fixed_.size(); ++i) {
    fixed_[i] = std::binary_search(fixed_rest_.begin(), fixed_rest_.end(),
                                   key_of(mesh_.rest, static_cast<int>(i)))
                    ? 1
                    : 0;
  }
  // Model::update_elements follows slot views that only grow (remeshing's): when the cut undid
  // temporary pieces and the arrays shrank, the model is rebuilt instead.
  const bool grew = mesh_.num_tets() >= tets_before && static_cast<std::size_t>(n) >= old_nodes;
  if (grew) {
    alive_.assign(static_cast<std::size_t>(mesh_.num_tets()), 1);
    model_->update_elements(mesh_, alive_, changed);
    ++local_updates_;
  } else {
    model_->update_topology(mesh_);
    ++full_updates_;
  }
  update_inverse_masses();
  rebuild_surface(grew ? &changed : nullptr);
  internal_.setZero(n, 3);
  forces_.setZero(n, 3);
}

}  // namespace incise::sim::surgery
