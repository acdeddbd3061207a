#include "sim/tools/damage_metrics.h"

namespace incise::sim::tools {

std::array<MetricRow, kDamageMetricCount> metric_rows(const DamageMetrics& m) {
  return {{
      {"damage.peak_strain", "1", m.peak_strain},
      {"damage.peak_strain_ratio", "1", m.peak_strain_ratio},
      {"damage.overstrained_elements", "count", Real(m.overstrained_elements)},
      {"damage.damaged_elements", "count", Real(m.damaged_elements)},
      {"damage.damaged_volume", "m^3", m.damaged_volume},
      {"damage.tracked_volume", "m^3", m.tracked_volume},
      {"damage.damage_index", "1", m.damage_index},
      {"damage.max_label_damage_index", "1", m.max_label_damage_index},
      {"damage.max_time_over_threshold", "s", m.max_time_over_threshold},
      {"damage.cut_events", "count", Real(m.cut_events)},
      {"damage.cut_area", "m^2", m.cut_area},
      {"damage.cut_area_outside_target", "m^2", m.cut_area_outside_target},
      {"damage.cut_mean_distance", "m", m.cut_mean_distance},
      {"damage.cut_max_distance", "m", m.cut_max_distance},
      {"damage.protected_cut_area", "m^2", m.protected_cut_area},
      {"damage.never_event", "flag", m.never_event ? Real(1) : Real(0)},
      {"damage.protected_collisions", "count", Real(m.protected_collisions)},
      {"damage.protected_contact_time", "s", m.protected_contact_time},
      {"damage.protected_peak_penetration", "m", m.protected_peak_penetration},
  }};
}

}  // namespace incise::sim::tools
