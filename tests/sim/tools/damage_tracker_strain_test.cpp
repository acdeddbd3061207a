// DamageTracker's strain part (sim/tools/damage_tracker.h) on a box stretched uniformly by 10%
// along x: every tet has the closed-form Green strain (1.1^2 - 1) / 2 = 0.105, so a threshold of
// 0.05 marks every tet, 0.2 none; times over the threshold, damaged volumes and damage indices
// follow exactly. Then damage carried over a topology change (a cut of the stretched box).

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "sim/cut/cut_mesh.h"
#include "sim/mesh/box_mesher.h"
#include "sim/tools/damage_tracker.h"

namespace incise::sim::tools {
namespace {

const Vec3 kSize(0.04, 0.02, 0.02);  // [m]
constexpr Real kStretch = 1.1;
constexpr Real kStrain = (kStretch * kStretch - 1) / 2;  // 0.105
constexpr Real kDt = 1.0 / 1024;                         // [s] a power of two: sums of it are exact
constexpr Real kBoxVolume = 0.04 * 0.02 * 0.02;

TetMesh box() {
  return make_box_mesh(kSize, Vec3i(4, 2, 2));
}

Points stretched(const TetMesh& mesh) {
  Points x = mesh.rest;
  x.col(0) *= kStretch;
  return x;
}

DamageSettings thresholds(std::vector<StrainThreshold> t) {
  DamageSettings settings;
  settings.strain_thresholds = std::move(t);
  return settings;
}

TEST(DamageStrainTracking, TenPercentStretchOverThresholdMarksEveryTet) {
  const TetMesh mesh = box();
  DamageTracker tracker(mesh, thresholds({{0, 0.05}}));
  const Points x = stretched(mesh);
  constexpr int kSteps = 100;
  for (int step = 0; step < kSteps; ++step)
    tracker.record_strain(x, kDt);

  const DamageMetrics m = tracker.metrics();
  EXPECT_EQ(m.overstrained_elements, mesh.num_tets());
  EXPECT_EQ(m.damaged_elements, mesh.num_tets());
  EXPECT_NEAR(m.peak_strain, kStrain, 1e-12);
  EXPECT_NEAR(m.peak_strain_ratio, kStrain / 0.05, 1e-10);
  EXPECT_EQ(m.max_time_over_threshold, kSteps * kDt);
  EXPECT_NEAR(m.damaged_volume, kBoxVolume, 1e-15);
  EXPECT_NEAR(m.tracked_volume, kBoxVolume, 1e-15);
  EXPECT_NEAR(m.damage_index, 1, 1e-12);
  EXPECT_NEAR(m.max_label_damage_index, 1, 1e-12);
  for (int s = 0; s < mesh.num_tets(); ++s) {
    EXPECT_NEAR(tracker.strain()(s), kStrain, 1e-12) << "slot " << s;
    EXPECT_NEAR(tracker.peak_strain()(s), kStrain, 1e-12) << "slot " << s;
    EXPECT_EQ(tracker.time_over_threshold()(s), kSteps * kDt) << "slot " << s;
    EXPECT_TRUE(tracker.damaged()[static_cast<std::size_t>(s)]) << "slot " << s;
  }
  ASSERT_EQ(tracker.label_damage().size(), 1u);
  EXPECT_NEAR(tracker.label_damage()[0].damage_index, 1, 1e-12);
}

TEST(DamageStrainTracking, TenPercentStretchUnderThresholdMarksNothing) {
  const TetMesh mesh = box();
  DamageTracker tracker(mesh, thresholds({{0, 0.2}}));
  const Points x = stretched(mesh);
  for (int step = 0; step < 20; ++step)
    tracker.record_strain(x, kDt);
  const DamageMetrics m = tracker.metrics();
  EXPECT_EQ(m.overstrained_elements, 0);
  EXPECT_EQ(m.damaged_elements, 0);
  EXPECT_EQ(m.damaged_volume, 0);
  EXPECT_EQ(m.damage_index, 0);
  EXPECT_EQ(m.max_time_over_threshold, 0);
  EXPECT_NEAR(m.peak_strain, kStrain, 1e-12);
  EXPECT_NEAR(m.peak_strain_ratio, kStrain / 0.2, 1e-10);
  EXPECT_NEAR(m.tracked_volume, kBoxVolume, 1e-15);
}

TEST(DamageStrainTracking, TimeCountsOnlyStepsOverThresholdAndDamageStays) {
  const TetMesh mesh = box();
  DamageTracker tracker(mesh, thresholds({{0, 0.05}}));
  const Points x = stretched(mesh);
  for (int step = 0; step < 30; ++step)
    tracker.record_strain(x, kDt);
  for (int step = 0; step < 50; ++step)
    tracker.record_strain(mesh.rest, kDt);
  for (int step = 0; step < 7; ++step)
    tracker.record_strain(x, 2 * kDt);
  for (int step = 0; step < 3; ++step)
    tracker.record_strain(mesh.rest, kDt);

  const DamageMetrics m = tracker.metrics();
  EXPECT_EQ(m.max_time_over_threshold, 30 * kDt + 7 * 2 * kDt);
  EXPECT_EQ(m.overstrained_elements, 0);  // relaxed at the last step
  EXPECT_EQ(m.damaged_elements, mesh.num_tets());
  EXPECT_NEAR(m.damage_index, 1, 1e-12);
  EXPECT_NEAR(m.peak_strain, kStrain, 1e-12);
  EXPECT_NEAR(tracker.strain().maxCoeff(), 0, 1e-14);
}

TEST(DamageStrainTracking, LabelsHaveTheirOwnThresholdsAndIndices) {
  // By cell layer along x: label 0 in x < 0.02 (threshold 0.05: damaged), label 1 in
  // [0.02, 0.03) (threshold 0.2: intact), label 2 beyond (no threshold: untracked).
  TetMesh mesh = box();
  const VecX volumes = tet_volumes(mesh.rest, mesh.tets);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    Real cx = 0;
    for (int k = 0; k < 4; ++k)
      cx += mesh.rest(mesh.tets(t, k), 0) / 4;
    mesh.labels(t) = cx < 0.02 ? 0 : (cx < 0.03 ? 1 : 2);
  }
  DamageTracker tracker(mesh, thresholds({{1, 0.2}, {0, 0.05}}));
  tracker.record_strain(stretched(mesh), kDt);
  const DamageMetrics m = tracker.metrics();
  const auto labels = tracker.label_damage();
  ASSERT_EQ(labels.size(), 2u);
  EXPECT_EQ(labels[0].label, 1);
  EXPECT_NEAR(labels[0].volume, kBoxVolume / 4, 1e-15);
  EXPECT_EQ(labels[0].damaged_volume, 0);
  EXPECT_EQ(labels[1].label, 0);
  EXPECT_NEAR(labels[1].volume, kBoxVolume / 2, 1e-15);
  EXPECT_NEAR(labels[1].damaged_volume, kBoxVolume / 2, 1e-15);
  EXPECT_NEAR(labels[1].damage_index, 1, 1e-12);
  EXPECT_NEAR(m.tracked_volume, 3 * kBoxVolume / 4, 1e-15);
  EXPECT_NEAR(m.damage_index, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(m.max_label_damage_index, 1, 1e-12);
  EXPECT_EQ(m.damaged_elements, mesh.num_tets() / 2);
  EXPECT_GT(volumes.minCoeff(), 0);
  for (int s = 0; s < mesh.num_tets(); ++s) {
    if (mesh.labels(s) == 2) {
      EXPECT_EQ(tracker.peak_strain()(s), 0) << "untracked slot " << s;
    }
  }
}

TEST(DamageStrainTracking, CutPiecesInheritTheirParentsDamage) {
  TetMesh mesh = box();
  DamageTracker tracker(mesh, thresholds({{0, 0.05}}));
  for (int step = 0; step < 10; ++step)
    tracker.record_strain(stretched(mesh), kDt);

  // Cut the box at rest along the plane x = 0.015 (inside the second cell layer).
  const Tets old_tets = mesh.tets;
  const std::vector<char> old_alive(static_cast<std::size_t>(mesh.num_tets()), 1);
  const cut::CutReport report =
      cut::cut_mesh(mesh, cut::blade_sweep(Vec3(0.015, -0.01, -0.01), Vec3(0.015, 0.03, -0.01),
                                           Vec3(0.015, -0.01, 0.03), Vec3(0.015, 0.03, 0.03)));
  ASSERT_GT(report.crack_faces.rows(), 0);
  ASSERT_GT(mesh.num_tets(), old_tets.rows());
  std::vector<int> parents;
  parents_by_rest_centroid(mesh.rest, old_tets, old_alive, mesh.tets, report.changed_tets, parents);
  for (const int p : parents)
    ASSERT_GE(p, 0);
  tracker.update_elements(mesh, std::vector<char>(static_cast<std::size_t>(mesh.num_tets()), 1),
                          report.changed_tets, parents);

  EXPECT_EQ(tracker.num_slots(), mesh.num_tets());
  const DamageMetrics m = tracker.metrics();
  EXPECT_EQ(m.damaged_elements, mesh.num_tets());
  EXPECT_NEAR(m.damaged_volume, kBoxVolume, 1e-15);
  EXPECT_NEAR(m.damage_index, 1, 1e-12);
  for (int s = 0; s < mesh.num_tets(); ++s) {
    EXPECT_EQ(tracker.time_over_threshold()(s), 10 * kDt) << "slot " << s;
    EXPECT_NEAR(tracker.peak_strain()(s), kStrain, 1e-12) << "slot " << s;
  }
  // The new pieces are strained like the rest under the same stretch.
  tracker.record_strain(stretched(mesh), kDt);
  EXPECT_EQ(tracker.metrics().overstrained_elements, mesh.num_tets());
  EXPECT_NEAR(tracker.strain().minCoeff(), kStrain, 1e-12);
}

TEST(DamageStrainTracking, FreshPiecesAndRemovedSlots) {
  TetMesh mesh = box();
  DamageTracker tracker(mesh, thresholds({{0, 0.05}}));
  tracker.record_strain(stretched(mesh), kDt);
  // Slot 0 dies; slot 1 is replaced by the same tet without history (parent -1).
  std::vector<char> alive(static_cast<std::size_t>(mesh.num_tets()), 1);
  alive[0] = 0;
  const VecX volumes = tet_volumes(mesh.rest, mesh.tets);
  const std::vector<int> changed = {0, 1};
  const std::vector<int> parents = {0, -1};
  tracker.update_elements(mesh, alive, changed, parents);
  const DamageMetrics m = tracker.metrics();
  EXPECT_EQ(m.damaged_elements, mesh.num_tets() - 2);
  EXPECT_NEAR(m.damaged_volume, kBoxVolume - volumes(0) - volumes(1), 1e-15);
  EXPECT_NEAR(m.tracked_volume, kBoxVolume - volumes(0), 1e-15);
  EXPECT_EQ(tracker.time_over_threshold()(1), 0);
  EXPECT_FALSE(tracker.damaged()[1]);
  EXPECT_EQ(tracker.time_over_threshold()(2), kDt);
}

}  // namespace
}  // namespace incise::sim::tools
