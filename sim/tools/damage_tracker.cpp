#include "sim/tools/damage_tracker.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/tools/damage_strain.h"

namespace incise::sim::tools {
namespace {

[[noreturn]] void fail(const char* where, const std::string& what) {
  throw std::invalid_argument(std::string("DamageTracker") + where + ": " + what);
}

void validate_settings(const DamageSettings& settings) {
  const auto& thresholds = settings.strain_thresholds;
  for (std::size_t i = 0; i < thresholds.size(); ++i) {
    const StrainThreshold& t = thresholds[i];
    if (!std::isfinite(t.max_principal_strain) || t.max_principal_strain <= 0)
      fail("", "the strain threshold of label " + std::to_string(t.label) +
                   " must be finite and > 0, got " + std::to_string(t.max_principal_strain));
    for (std::size_t j = 0; j < i; ++j) {
      if (thresholds[j].label == t.label)
        fail("", "label " + std::to_string(t.label) + " has two strain thresholds");
    }
  }
  if (settings.protected_structures < 0)
    fail("",
         "protected_structures must be >= 0, got " + std::to_string(settings.protected_structures));
  validate_target(settings.target);
}

void check_dt(const char* where, Real dt) {
  if (!std::isfinite(dt) || dt <= 0)
    fail(where, "dt must be finite and > 0, got " + std::to_string(dt) + " s");
}

}  // namespace

DamageTracker::DamageTracker(const TetMesh& mesh, DamageSettings settings)
    : DamageTracker(mesh, std::vector<char>(static_cast<std::size_t>(mesh.num_tets()), 1),
                    std::move(settings)) {}

DamageTracker::DamageTracker(const TetMesh& mesh, const std::vector<char>& alive,
                             DamageSettings settings)
    : settings_(std::move(settings)) {
  validate_settings(settings_);
  for (const StrainThreshold& t : settings_.strain_thresholds)
    labels_.push_back({t.label, t.max_principal_strain, 0, 0, 0});
  structures_.resize(static_cast<std::size_t>(settings_.protected_structures));

  const int slots = mesh.num_tets();
  if (alive.size() != static_cast<std::size_t>(slots))
    fail("", "alive has " + std::to_string(alive.size()) + " entries for " + std::to_string(slots) +
                 " tet slots");
  tets_ = mesh.tets;
  alive_ = alive;
  label_.assign(static_cast<std::size_t>(slots), 0);
  label_index_.assign(static_cast<std::size_t>(slots), -1);
  rest_inverse_.assign(static_cast<std::size_t>(slots), Mat3::Zero());
  rest_volume_ = VecX::Zero(slots);
  strain_ = VecX::Zero(slots);
  peak_ = VecX::Zero(slots);
  time_over_ = VecX::Zero(slots);
  damaged_.assign(static_cast<std::size_t>(slots), 0);
  for (int s = 0; s < slots; ++s) {
    if (alive_[static_cast<std::size_t>(s)]) set_slot(mesh, s);
  }
  recompute_volumes();
}

void DamageTracker::set_slot(const TetMesh& mesh, int s) {
  if (mesh.labels.size() != mesh.tets.rows())
    fail("", "the mesh has " + std::to_string(mesh.labels.size()) + " labels for " +
                 std::to_string(mesh.tets.rows()) + " tet slots");
  Vec3 corner[4];
  for (int k = 0; k < 4; ++k) {
    const int node = mesh.tets(s, k);
    if (node < 0 || node >= mesh.rest.rows())
      fail("", "tet slot " + std::to_string(s) + " holds node " + std::to_string(node) +
                   ", outside [0, " + std::to_string(mesh.rest.rows()) + ")");
    corner[k] = row3(mesh.rest, node);
  }
  const auto i = static_cast<std::size_t>(s);
  const Real volume =
      rest_edge_inverse(corner[0], corner[1], corner[2], corner[3], rest_inverse_[i]);
  if (!(volume > 0))
    fail("", "tet slot " + std::to_string(s) + " has rest volume " + std::to_string(volume) +
                 " m^3 (flat or inverted at rest)");
  rest_volume_(s) = volume;
  label_[i] = mesh.labels(s);
  label_index_[i] = -1;
  for (std::size_t l = 0; l < labels_.size(); ++l) {
    if (labels_[l].label == label_[i]) label_index_[i] = static_cast<int>(l);
  }
}

void DamageTracker::recompute_volumes() {
  for (LabelDamage& l : labels_)
    l.volume = l.damaged_volume = 0;
  totals_.damaged_elements = 0;
  min_rows_ = 0;
  tracked_.assign(static_cast<std::size_t>(num_slots()), 0);
  for (int s = 0; s < num_slots(); ++s) {
    const auto i = static_cast<std::size_t>(s);
    tracked_[i] = alive_[i] && label_index_[i] >= 0 ? 1 : 0;
    if (!alive_[i]) continue;
    min_rows_ = std::max(min_rows_, tets_.row(s).maxCoeff() + 1);
    if (label_index_[i] < 0) continue;
    LabelDamage& l = labels_[static_cast<std::size_t>(label_index_[i])];
    l.volume += rest_volume_(s);
    if (damaged_[i]) {
      l.damaged_volume += rest_volume_(s);
      ++totals_.damaged_elements;
    }
  }
  for (LabelDamage& l : labels_)
    l.damage_index = l.volume > 0 ? l.damaged_volume / l.volume : 0;
}

void DamageTracker::record_strain(const Points& x, Real dt) {
  check_dt("::record_strain", dt);
  if (x.rows() < min_rows_)
    fail("::record_strain", "x has " + std::to_string(x.rows()) + " rows, the tets use " +
                                std::to_string(min_rows_) + " nodes");
  // Two passes, so that a NaN found in the first leaves the damage state as it was.
  max_principal_green_strains(num_slots(), tets_.data(), x.data(), rest_inverse_.data(),
                              tracked_.data(), strain_.data());
  for (int s = 0; s < num_slots(); ++s) {
    if (!std::isfinite(strain_(s)))
      fail("::record_strain", "the strain of tet slot " + std::to_string(s) +
                                  " is not finite (x holds NaN or infinity)");
  }
  int over = 0;
  for (int s = 0; s < num_slots(); ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (!alive_[i] || label_index_[i] < 0) continue;
    LabelDamage& l = labels_[static_cast<std::size_t>(label_index_[i])];
    const Real e = strain_(s);
    peak_(s) = std::max(peak_(s), e);
    totals_.peak_strain = std::max(totals_.peak_strain, e);
    totals_.peak_strain_ratio = std::max(totals_.peak_strain_ratio, e / l.threshold);
    if (!(e > l.threshold)) continue;
    ++over;
    time_over_(s) += dt;
    totals_.max_time_over_threshold = std::max(totals_.max_time_over_threshold, time_over_(s));
    if (!damaged_[i]) {
      damaged_[i] = 1;
      l.damaged_volume += rest_volume_(s);
      l.damage_index = l.damaged_volume / l.volume;
      ++totals_.damaged_elements;
    }
  }
  totals_.overstrained_elements = over;
}

void DamageTracker::update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                                    std::span<const int> changed, std::span<const int> parents) {
  const int old_slots = num_slots();
  const int slots = mesh.num_tets();
  if (alive.size() != static_cast<std::size_t>(slots))
    fail("::update_elements", "alive has " + std::to_string(alive.size()) + " entries for " +
                                  std::to_string(slots) + " tet slots");
  if (parents.size() != changed.size())
    fail("::update_elements", "parents has " + std::to_string(parents.size()) + " entries for " +
                                  std::to_string(changed.size()) + " changed slots");
  for (std::size_t k = 0; k < changed.size(); ++k) {
    if (changed[k] < 0 || changed[k] >= slots)
      fail("::update_elements", "changed slot " + std::to_string(changed[k]) + " is outside [0, " +
                                    std::to_string(slots) + ")");
    if (parents[k] < -1 || parents[k] >= old_slots)
      fail("::update_elements", "parent " + std::to_string(parents[k]) + " of slot " +
                                    std::to_string(changed[k]) + " is outside [-1, " +
                                    std::to_string(old_slots) + ")");
  }
  if (slots < old_slots)
    fail("::update_elements", "the mesh has " + std::to_string(slots) + " tet slots, fewer than " +
                                  std::to_string(old_slots) + " (slots are never removed)");

  // Work on a copy and commit at the end: a bad new tet leaves the tracker as it was. The
  // parents' states are read from the pre-update arrays (a slot may be its own piece's parent).
  DamageTracker next = *this;
  const auto n = static_cast<std::size_t>(slots);
  next.tets_ = mesh.tets;
  next.alive_ = alive;
  next.label_.resize(n, 0);
  next.label_index_.resize(n, -1);
  next.rest_inverse_.resize(n, Mat3::Zero());
  next.rest_volume_.conservativeResize(slots);
  next.strain_.conservativeResize(slots);
  next.peak_.conservativeResize(slots);
  next.time_over_.conservativeResize(slots);
  next.damaged_.resize(n, 0);
  for (int s = old_slots; s < slots; ++s) {
    next.rest_volume_(s) = next.strain_(s) = next.peak_(s) = next.time_over_(s) = 0;
  }
  for (std::size_t k = 0; k < changed.size(); ++k) {
    const int s = changed[k];
    const int p = parents[k];
    const auto i = static_cast<std::size_t>(s);
    next.strain_(s) = 0;
    next.peak_(s) = p < 0 ? Real(0) : peak_(p);
    next.time_over_(s) = p < 0 ? Real(0) : time_over_(p);
    next.damaged_[i] = p < 0 ? char(0) : damaged_[static_cast<std::size_t>(p)];
    if (alive[i]) {
      next.set_slot(mesh, s);
    } else {
      next.rest_volume_(s) = next.peak_(s) = next.time_over_(s) = 0;
      next.damaged_[i] = 0;
      next.label_index_[i] = -1;
    }
  }
  next.recompute_volumes();
  *this = std::move(next);
}

void DamageTracker::record_contacts(std::span<const Real> depths, Real dt) {
  check_dt("::record_contacts", dt);
  if (depths.size() != structures_.size())
    fail("::record_contacts", "got " + std::to_string(depths.size()) + " depths for " +
                                  std::to_string(structures_.size()) + " protected structures");
  for (std::size_t k = 0; k < depths.size(); ++k) {
    if (!std::isfinite(depths[k]))
      fail("::record_contacts",
           "the depth of protected structure " + std::to_string(k) + " is not finite");
  }
  bool any = false;
  for (std::size_t k = 0; k < depths.size(); ++k) {
    StructureContact& c = structures_[k];
    const bool touching = depths[k] > 0;
    if (touching && !c.touching) {
      ++c.collisions;
      ++totals_.protected_collisions;
    }
    c.touching = touching;
    if (!touching) continue;
    any = true;
    c.contact_time += dt;
    c.peak_penetration = std::max(c.peak_penetration, depths[k]);
    totals_.protected_peak_penetration = std::max(totals_.protected_peak_penetration, depths[k]);
  }
  if (any) totals_.protected_contact_time += dt;
}

DamageMetrics DamageTracker::metrics() const {
  DamageMetrics m = totals_;
  for (const LabelDamage& l : labels_) {
    m.damaged_volume += l.damaged_volume;
    m.tracked_volume += l.volume;
    if (l.volume > 0)
      m.max_label_damage_index = std::max(m.max_label_damage_index, l.damaged_volume / l.volume);
  }
  m.damage_index = m.tracked_volume > 0 ? m.damaged_volume / m.tracked_volume : Real(0);
  m.cut_mean_distance = m.cut_area > 0 ? weighted_distance_ / m.cut_area : Real(0);
  return m;
}

}  // namespace incise::sim::tools
