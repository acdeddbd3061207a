#include "sim/solve/active_region.h"

#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

#include "sim/mesh/box_mesher.h"

namespace incise::sim {
namespace {

ActiveRegionSettings settings(int sleep_frames = 3) {
  ActiveRegionSettings s;
  s.sleep_speed = 1e-3;
  s.sleep_force = 1e-3;
  s.wake_force = 2e-3;
  s.sleep_frames = sleep_frames;
  return s;
}

TEST(ActiveRegion, RejectsSettingsWithoutHysteresisOrOutOfRange) {
  const TetMesh mesh = make_box_mesh(Vec3::Ones(), Vec3i(1, 1, 1));
  ActiveRegionSettings s = settings();
  s.wake_force = s.sleep_force;
  EXPECT_THROW(ActiveRegion(mesh.tets, mesh.num_nodes(), s), std::invalid_argument);
  s = settings(0);
  EXPECT_THROW(ActiveRegion(mesh.tets, mesh.num_nodes(), s), std::invalid_argument);
  s = settings();
  s.sleep_speed = -1;
  EXPECT_THROW(ActiveRegion(mesh.tets, mesh.num_nodes(), s), std::invalid_argument);
  EXPECT_THROW(ActiveRegion(mesh.tets, mesh.num_nodes() - 1, settings()), std::invalid_argument);
}

TEST(ActiveRegion, SetsFollowTheDefinitionsOnEveryNodeOfABox) {
  // For each single woken node: active tets = the tets at it; complete nodes = the nodes of those
  // tets; evaluated tets = the tets touching a complete node. Checked by brute force.
  const TetMesh mesh = make_box_mesh(Vec3::Ones(), Vec3i(3, 3, 2));
  for (int woken = 0; woken < mesh.num_nodes(); ++woken) {
    ActiveRegion region(mesh.tets, mesh.num_nodes(), settings());
    region.update_sets();
    EXPECT_TRUE(region.active_tets().empty());
    EXPECT_TRUE(region.evaluated_tets().empty());
    ASSERT_TRUE(region.wake(woken));
    EXPECT_FALSE(region.wake(woken));  // already awake
    EXPECT_TRUE(region.changed());
    region.update_sets();
    EXPECT_FALSE(region.changed());
    std::vector<int> active_tets;
    std::set<int> complete;
    for (int t = 0; t < mesh.num_tets(); ++t) {
      if ((mesh.tets.row(t).array() == woken).any()) {
        active_tets.push_back(t);
        for (int k = 0; k < 4; ++k)
          complete.insert(mesh.tets(t, k));
      }
    }
    std::vector<int> evaluated;
    for (int t = 0; t < mesh.num_tets(); ++t) {
      bool touches = false;
      for (int k = 0; k < 4; ++k)
        touches = touches || complete.count(mesh.tets(t, k)) > 0;
      if (touches) evaluated.push_back(t);
    }
    EXPECT_EQ(region.active_nodes(), std::vector<int>{woken});
    EXPECT_EQ(region.active_tets(), active_tets);
    EXPECT_EQ(region.complete_nodes(), std::vector<int>(complete.begin(), complete.end()));
    EXPECT_EQ(region.evaluated_tets(), evaluated);
  }
}

TEST(ActiveRegion, SleepsAfterSleepFramesCalmStepsAndACalmRunRestarts) {
  const TetMesh mesh = make_box_mesh(Vec3::Ones(), Vec3i(1, 1, 1));
  ActiveRegion region(mesh.tets, mesh.num_nodes(), settings(3));
  region.wake(0);
  region.update_sets();
  EXPECT_FALSE(region.observe(0, 0, 0));
  EXPECT_FALSE(region.observe(0, 0, 0));
  EXPECT_FALSE(region.observe(0, 2e-3, 0));  // too fast: the count restarts
  EXPECT_FALSE(region.observe(0, 0, 0));
  EXPECT_FALSE(region.observe(0, 0, 5e-3));  // too much force: restarts again
  EXPECT_FALSE(region.observe(0, 0, 0));
  EXPECT_FALSE(region.observe(0, 0, 0));
  EXPECT_TRUE(region.observe(0, 0, 0));
  EXPECT_FALSE(region.node_active(0));
  EXPECT_TRUE(region.changed());
  EXPECT_FALSE(region.observe(0, 0, 0));  // asleep: nothing to observe
}

TEST(ActiveRegion, ForcesBetweenTheThresholdsNeitherWakeNorPutToSleep) {
  const TetMesh mesh = make_box_mesh(Vec3::Ones(), Vec3i(1, 1, 1));
  const ActiveRegionSettings s = settings(1);
  ActiveRegion region(mesh.tets, mesh.num_nodes(), s);
  const Real between = (s.sleep_force + s.wake_force) / 2;
  EXPECT_FALSE(region.should_wake(between));
  EXPECT_TRUE(region.should_wake(1.01 * s.wake_force));
  region.wake(0);
  for (int i = 0; i < 10; ++i)
    EXPECT_FALSE(region.observe(0, 0, between));
  EXPECT_TRUE(region.node_active(0));
}

TEST(ActiveRegion, FixedNodesNeverWake) {
  const TetMesh mesh = make_box_mesh(Vec3::Ones(), Vec3i(1, 1, 1));
  ActiveRegion region(mesh.tets, mesh.num_nodes(), settings());
  region.fix(2);
  EXPECT_FALSE(region.wake(2));
  EXPECT_TRUE(region.node_fixed(2));
  region.update_sets();
  EXPECT_TRUE(region.active_tets().empty());
}

}  // namespace
}  // namespace incise::sim
