// DamageTracker's contacts with protected structures (sim/tools/damage_tracker.h) over scripted
// on/off sequences, deepest_contact, and the metric rows (sim/tools/damage_metrics.h).

#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/mesh/box_mesher.h"
#include "sim/tools/damage_tracker.h"

namespace incise::sim::tools {
namespace {

constexpr Real kDt = 1.0 / 256;  // [s] sums of it are exact

DamageTracker two_structures() {
  DamageSettings settings;
  settings.protected_structures = 2;
  return DamageTracker(make_box_mesh(Vec3(1, 1, 1), Vec3i(1, 1, 1)), settings);
}

TEST(DamageContact, RisingEdgesTimeAndPeakOfAScriptedSequence) {
  // Per step, the depth [m] into structure 0 and structure 1 (<= 0: apart).
  const std::vector<std::array<Real, 2>> script = {
      {0, 0},                       // apart
      {0.001, 0},                   // 0 touches: event 1 of 0
      {0.003, 0},                   // still touching: no event
      {0, 0.002},                   // 0 leaves, 1 touches: event 1 of 1
      {-0.001, 0.001},              // 1 still touching
      {0.0005, 0},                  // 0 again: event 2 of 0; 1 leaves
      {0.0005, 0.004},              // 1 again: event 2 of 1
      {0, 0},                       // both apart
      {0, 0},          {0.002, 0},  // 0: event 3
  };
  DamageTracker tracker = two_structures();
  for (const auto& depths : script)
    tracker.record_contacts(depths, kDt);

  const auto structures = tracker.structure_contacts();
  ASSERT_EQ(structures.size(), 2u);
  EXPECT_EQ(structures[0].collisions, 3);
  EXPECT_EQ(structures[0].contact_time, 5 * kDt);
  EXPECT_EQ(structures[0].peak_penetration, 0.003);
  EXPECT_TRUE(structures[0].touching);
  EXPECT_EQ(structures[1].collisions, 2);
  EXPECT_EQ(structures[1].contact_time, 3 * kDt);
  EXPECT_EQ(structures[1].peak_penetration, 0.004);
  EXPECT_FALSE(structures[1].touching);

  const DamageMetrics m = tracker.metrics();
  EXPECT_EQ(m.protected_collisions, 5);
  EXPECT_EQ(m.protected_contact_time, 7 * kDt);  // steps 1-6 and 9 touch something
  EXPECT_EQ(m.protected_peak_penetration, 0.004);
}

TEST(DamageContact, ContactHeldAcrossManyStepsIsOneEvent) {
  DamageTracker tracker = two_structures();
  for (int step = 0; step < 1000; ++step)
    tracker.record_contacts(std::array<Real, 2>{1e-4, 0}, kDt);
  EXPECT_EQ(tracker.metrics().protected_collisions, 1);
  EXPECT_EQ(tracker.metrics().protected_contact_time, 1000 * kDt);
}

TEST(DamageContact, DeepestContactCountsOnlyProtectedTriangles) {
  std::vector<collide::Contact> contacts(3);
  contacts[0].triangle = 0, contacts[0].depth = 0.005;
  contacts[1].triangle = 2, contacts[1].depth = 0.002;
  contacts[2].triangle = 1, contacts[2].depth = 0.001;
  EXPECT_EQ(deepest_contact(contacts), 0.005);
  const std::vector<char> protect = {0, 1, 1};
  EXPECT_EQ(deepest_contact(contacts, protect), 0.002);
  EXPECT_EQ(deepest_contact({}, protect), 0);
  const std::vector<char> short_flags = {1, 1};
  EXPECT_THROW(
      {
        try {
          deepest_contact(contacts, short_flags);
        } catch (const std::invalid_argument& e) {
          EXPECT_STREQ(e.what(), "deepest_contact: contact triangle 2 is outside [0, 2)");
          throw;
        }
      },
      std::invalid_argument);
}

TEST(DamageMetricRows, EveryFieldOnceWithStableNamesAndUnits) {
  DamageMetrics m;
  m.peak_strain = 0.1;
  m.overstrained_elements = 4;
  m.damage_index = 0.25;
  m.cut_area_outside_target = 3e-4;
  m.never_event = true;
  m.protected_collisions = 2;
  m.protected_peak_penetration = 0.004;
  const auto rows = metric_rows(m);
  std::set<std::string> names;
  for (const MetricRow& row : rows) {
    EXPECT_EQ(row.name.substr(0, 7), "damage.") << row.name;
    EXPECT_FALSE(row.unit.empty()) << row.name;
    names.insert(std::string(row.name));
  }
  EXPECT_EQ(names.size(), rows.size());
  // The order is part of the contract: first, last and a few in between.
  EXPECT_EQ(rows.front().name, "damage.peak_strain");
  EXPECT_EQ(rows.front().value, 0.1);
  EXPECT_EQ(rows[2].name, "damage.overstrained_elements");
  EXPECT_EQ(rows[2].value, 4);
  EXPECT_EQ(rows[6].name, "damage.damage_index");
  EXPECT_EQ(rows[6].value, 0.25);
  EXPECT_EQ(rows[11].name, "damage.cut_area_outside_target");
  EXPECT_EQ(rows[11].unit, "m^2");
  EXPECT_EQ(rows[11].value, 3e-4);
  EXPECT_EQ(rows[15].name, "damage.never_event");
  EXPECT_EQ(rows[15].unit, "flag");
  EXPECT_EQ(rows[15].value, 1);
  EXPECT_EQ(rows[16].value, 2);
  EXPECT_EQ(rows.back().name, "damage.protected_peak_penetration");
  EXPECT_EQ(rows.back().unit, "m");
  EXPECT_EQ(rows.back().value, 0.004);
}

}  // namespace
}  // namespace incise::sim::tools
