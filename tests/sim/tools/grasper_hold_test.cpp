// Holding (sim/tools/grasper.h): the grabbed vertices follow the jaw frame's rigid motion
// exactly, through prescribe() and through hold() alike; opening releases without touching the
// state; jaws closed on empty space grab nothing, not even when pushed into tissue afterwards;
// Newton's third law for the pull and the momentum it gives the free vertices.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "grasp_fixtures.h"

namespace incise::sim::tools {
namespace {

using testing::GraspedBlock;

// A rigid motion p -> rotation (p - centre) + centre + shift, applied to a pose.
struct RigidMotion {
  Mat3 rotation = Mat3::Identity();
  Vec3 centre = Vec3::Zero();
  Vec3 shift = Vec3::Zero();

  Vec3 point(const Vec3& p) const { return rotation * (p - centre) + centre + shift; }
  JawPose pose(const JawPose& pose) const {
    JawPose moved = pose;
    moved.pivot = point(pose.pivot);
    moved.direction = rotation * pose.direction;
    moved.opening_normal = rotation * pose.opening_normal;
    return moved;
  }
};

// Step k of a tumbling, drifting tool: about a tilted axis through the tips, 0.02 rad a step.
RigidMotion motion_at(int k, const Vec3& centre) {
  RigidMotion m;
  m.rotation = Eigen::AngleAxis<Real>(0.02 * k, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  m.centre = centre;
  m.shift = Vec3(0.0002, -0.0001, 0.0003) * k;
  return m;
}

GraspSettings wide_jaws() {
  GraspSettings s;
  s.jaw_radius = 0.003;
  s.grab_margin = 0.0025;
  s.tear_force = std::numeric_limits<Real>::infinity();
  return s;
}

const Vec3 kTopCentre(0.01, 0.01, 0.02);

TEST(GraspHold, GrabbedVerticesFollowTheJawFrameRigidly) {
  GraspedBlock block(MaterialModel::corotational, Vec3(0.02, 0.02, 0.02), Vec3i(4, 4, 4), false);
  // The same run through hold() after a free step (how an AdaptiveBody is driven).
  GraspedBlock other(MaterialModel::corotational, Vec3(0.02, 0.02, 0.02), Vec3i(4, 4, 4), false);
  Grasper grasper(wide_jaws());
  Grasper other_grasper(wide_jaws());
  const JawPose start = testing::downward_jaws(kTopCentre + Vec3(0, 0, 0.01), 0.05);

  block.step(grasper, start);
  const std::vector<int> held = grasper.grabbed();
  ASSERT_EQ(held.size(), 5u);
  const Points grabbed_at = block.start_x;

  other_grasper.set_jaws(start);
  ASSERT_EQ(other_grasper.grab(other.mesh.rest, other.mesh.x, other.inverse_masses, other.surface),
            5);
  Prescribed none;
  Points f = Points::Zero(other.mesh.num_nodes(), 3);
  auto free_step_then_hold = [&]() {
    f.setZero();
    other.model->add_forces(other.mesh.x, other.mesh.v, f);
    symplectic_euler_step(other.dt, Vec3::Zero(), other.inverse_masses, none, f, other.mesh.x,
                          other.mesh.v);
    other_grasper.hold(other.dt, other.mesh.x, other.mesh.v);
  };
  free_step_then_hold();

  Real largest_error = 0;
  for (int k = 1; k <= 40; ++k) {
    const RigidMotion m = motion_at(k, kTopCentre);
    ASSERT_FALSE(block.step(grasper, m.pose(start)).has_value());
    ASSERT_FALSE(other_grasper.set_jaws(m.pose(start)).has_value());
    free_step_then_hold();
    const RigidMotion before = motion_at(k - 1, kTopCentre);
    for (std::size_t j = 0; j < held.size(); ++j) {
      const int i = held[j];
      const Vec3 expected = m.point(row3(grabbed_at, i));
      largest_error = std::max(largest_error, (row3(block.mesh.x, i) - expected).norm());
      EXPECT_NEAR((row3(block.mesh.x, i) - grasper.held_position(j)).norm(), 0, 1e-15);
      // Velocities: the frame's displacement over the step, both ways.
      const Vec3 velocity = (expected - before.point(row3(grabbed_at, i))) / block.dt;
      EXPECT_LT((row3(block.mesh.v, i) - velocity).norm(), 1e-9 * velocity.norm() + 1e-12);
      EXPECT_LT((row3(other.mesh.x, i) - row3(block.mesh.x, i)).norm(), 1e-15);
      EXPECT_LT((row3(other.mesh.v, i) - row3(block.mesh.v, i)).norm(),
                1e-9 * velocity.norm() + 1e-12);
    }
  }
  // Exact up to round-off (0.8 rad turned, 1 cm moved).
  std::printf("[ grasp ] largest distance from the rigid motion: %.2e m\n", largest_error);
  EXPECT_LT(largest_error, 1e-12);
  // The two drivings give the same body (the free vertices never saw a difference).
  EXPECT_LT((other.mesh.x - block.mesh.x).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(GraspHold, OpeningReleasesWithoutTouchingTheState) {
  GraspedBlock block(MaterialModel::mass_spring, Vec3(0.02, 0.02, 0.02), Vec3i(4, 4, 4), true);
  Grasper grasper(wide_jaws());
  const JawPose start = testing::downward_jaws(kTopCentre + Vec3(0, 0, 0.01), 0);
  constexpr int kSteps = 200;
  for (int k = 0; k < kSteps; ++k) {
    JawPose pose = start;
    pose.pivot.z() += 0.005 * k / kSteps;
    ASSERT_FALSE(block.step(grasper, pose).has_value());
  }
  ASSERT_EQ(grasper.phase(), GraspPhase::holding);
  const std::vector<int> held = grasper.grabbed();
  const Vec3 pull = grasper.pull();
  EXPECT_GT(pull.z(), 0);

  // The jaws open where they are.
  const Points x = block.mesh.x;
  const Points v = block.mesh.v;
  Points before = Points::Zero(x.rows(), 3);
  block.model->add_forces(x, v, before);
  JawPose opened = start;
  opened.pivot.z() += 0.005 * (kSteps - 1) / kSteps;
  opened.opening_angle = grasper.settings().open_angle;
  const std::optional<ReleaseEvent> event = grasper.set_jaws(opened);
  ASSERT_TRUE(event.has_value());
  EXPECT_EQ(event->reason, ReleaseReason::opened);
  EXPECT_EQ(event->released_vertices, static_cast<int>(held.size()));
  EXPECT_EQ(event->pull, pull);
  EXPECT_EQ(grasper.phase(), GraspPhase::open);
  EXPECT_TRUE(grasper.grabbed().empty());
  EXPECT_EQ(grasper.pull(), Vec3::Zero());
  // The resimplify region covers the held vertices' rest points.
  for (const int i : held) {
    EXPECT_LE((row3(block.mesh.rest, i) - event->resimplify.centre).norm(),
              event->resimplify.radius);
  }
  // Nothing moved and no force changed at the release: no jump on any vertex.
  EXPECT_EQ(block.mesh.x, x);
  EXPECT_EQ(block.mesh.v, v);
  Points after = Points::Zero(x.rows(), 3);
  block.model->add_forces(block.mesh.x, block.mesh.v, after);
  EXPECT_EQ(after, before);
  // The held vertices leave at the jaws' velocity and are free from now on: the tissue pulls
  // them back down.
  Prescribed prescribed{AxisMask::Zero(x.rows(), 3), Points::Zero(x.rows(), 3)};
  grasper.prescribe(prescribed);
  EXPECT_EQ(prescribed.mask.cast<int>().sum(), 0);
  for (const int i : held)
    EXPECT_NEAR(block.mesh.v(i, 2), 0.005 / kSteps / block.dt, 1e-9);
  for (int k = 0; k < 50; ++k)
    block.step(grasper, opened);
  for (const int i : held)
    EXPECT_LT(block.mesh.x(i, 2), x(i, 2));
}

TEST(GraspHold, JawsClosedOnEmptySpaceGrabNothing) {
  GraspedBlock block(MaterialModel::mass_spring, Vec3(0.02, 0.02, 0.02), Vec3i(4, 4, 4), true);
  Grasper grasper(wide_jaws());
  // Closed 2 cm above the top face: beyond the jaws and beyond reach.
  const JawPose above = testing::downward_jaws(kTopCentre + Vec3(0, 0, 0.03), 0);
  EXPECT_FALSE(block.step(grasper, above).has_value());
  EXPECT_EQ(grasper.phase(), GraspPhase::closed_empty);
  EXPECT_TRUE(grasper.grabbed().empty());
  // Pushed into the tissue closed: still nothing (a grab happens only at the closing).
  const JawPose inside = testing::downward_jaws(kTopCentre + Vec3(0, 0, 0.01), 0);
  block.step(grasper, inside);
  EXPECT_EQ(grasper.phase(), GraspPhase::closed_empty);
  EXPECT_THROW(grasper.grab(block.mesh.rest, block.mesh.x, block.inverse_masses, block.surface),
               std::logic_error);
  // Opened and closed again there: it grabs.
  JawPose opened = inside;
  opened.opening_angle = 0.5;
  block.step(grasper, opened);
  EXPECT_EQ(grasper.phase(), GraspPhase::open);
  block.step(grasper, inside);
  EXPECT_EQ(grasper.phase(), GraspPhase::holding);
  EXPECT_EQ(grasper.grabbed().size(), 5u);
}

TEST(GraspHold, NearestVertexWithinReachWhenTheJawsMissEveryVertex) {
  GraspedBlock block(MaterialModel::mass_spring, Vec3(0.02, 0.02, 0.02), Vec3i(2, 2, 2), true);
  GraspSettings s;  // jaw radius 1 mm + margin 0.5 mm, reach 3 mm
  // Tips 2 mm above the top centre node: outside the jaws, within reach.
  Grasper grasper(s);
  block.step(grasper, testing::downward_jaws(kTopCentre + Vec3(0, 0, 0.002 + s.jaw_length), 0));
  ASSERT_EQ(grasper.grabbed().size(), 1u);
  EXPECT_EQ(row3(block.mesh.rest, grasper.grabbed()[0]), kTopCentre);
  // 4 mm above: out of reach.
  Grasper far(s);
  block.step(far, testing::downward_jaws(kTopCentre + Vec3(0, 0, 0.004 + s.jaw_length), 0));
  EXPECT_TRUE(far.grabbed().empty());
  EXPECT_EQ(far.phase(), GraspPhase::closed_empty);
}

TEST(GraspHold, PullIsMinusTheTissueForceAndTheMomentumOfTheFreeVertices) {
  // A free block (nothing clamped, gravity off) dragged and turned by the jaws.
  GraspedBlock block(MaterialModel::corotational, Vec3(0.02, 0.02, 0.02), Vec3i(4, 4, 4), false);
  Grasper grasper(wide_jaws());
  const JawPose start = testing::downward_jaws(kTopCentre + Vec3(0, 0, 0.01), 0);
  const VecX& m = block.model->masses();
  auto free_momentum = [&](const std::vector<int>& held) {
    std::vector<char> is_held(static_cast<std::size_t>(m.size()), 0);
    for (const int i : held)
      is_held[static_cast<std::size_t>(i)] = 1;
    Vec3 p = Vec3::Zero();
    for (int i = 0; i < m.size(); ++i) {
      if (is_held[static_cast<std::size_t>(i)] == 0) p += m[i] * row3(block.mesh.v, i);
    }
    return p;
  };
  Vec3 impulse = Vec3::Zero();
  Real impulse_scale = 0;
  std::vector<int> held;
  Vec3 p0 = Vec3::Zero();
  for (int k = 0; k < 150; ++k) {
    ASSERT_FALSE(block.step(grasper, motion_at(k, kTopCentre).pose(start)).has_value());
    if (k == 0) {
      held = grasper.grabbed();
      ASSERT_EQ(held.size(), 5u);
      p0 = free_momentum(held);  // all zero: the body started at rest
    }
    Vec3 tissue_on_held = Vec3::Zero();
    for (const int i : held)
      tissue_on_held += row3(block.forces, i);
    EXPECT_EQ(grasper.pull(), -tissue_on_held);
    impulse += block.dt * grasper.pull();
    impulse_scale += block.dt * grasper.pull().norm();
  }
  ASSERT_GT(impulse.norm(), 0.1 * impulse_scale);  // a real net pull, not cancelling noise
  const Vec3 change = free_momentum(held) - p0;
  std::printf("[ grasp ] impulse %.4e N s, |momentum change - impulse| %.2e N s\n", impulse.norm(),
              (change - impulse).norm());
  EXPECT_LT((change - impulse).norm(), 1e-9 * impulse_scale)
      << "momentum change " << change.transpose() << ", impulse " << impulse.transpose();
}

TEST(GraspHold, RemovedAndRenumberedVerticesAreFollowed) {
  GraspedBlock block(MaterialModel::mass_spring, Vec3(0.02, 0.02, 0.02), Vec3i(4, 4, 4), true);
  Grasper grasper(wide_jaws());
  const JawPose pose = testing::downward_jaws(kTopCentre + Vec3(0, 0, 0.01), 0);
  block.step(grasper, pose);
  const std::vector<int> held = grasper.grabbed();
  ASSERT_EQ(held.size(), 5u);
  std::vector<Vec3> targets;
  for (std::size_t k = 0; k < held.size(); ++k)
    targets.push_back(grasper.held_position(k));

  // Reverse the numbering: each held vertex keeps its target under its new number.
  const int n = block.mesh.num_nodes();
  std::vector<int> reversed(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    reversed[static_cast<std::size_t>(i)] = n - 1 - i;
  EXPECT_FALSE(grasper.remap(reversed).has_value());
  ASSERT_EQ(grasper.grabbed().size(), held.size());
  for (std::size_t k = 0; k < grasper.grabbed().size(); ++k) {
    const int now = grasper.grabbed()[k];
    const auto j =
        static_cast<std::size_t>(std::find(held.begin(), held.end(), n - 1 - now) - held.begin());
    ASSERT_LT(j, held.size());
    EXPECT_EQ(grasper.held_position(k), targets[j]);
  }
  // Renumbering that drops one, then removals: the grasp ends (lost) with the last one.
  std::vector<int> identity(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    identity[static_cast<std::size_t>(i)] = i;
  identity[static_cast<std::size_t>(grasper.grabbed()[0])] = -1;
  EXPECT_FALSE(grasper.remap(identity).has_value());
  EXPECT_EQ(grasper.grabbed().size(), 4u);
  EXPECT_FALSE(grasper.on_vertex_removed(-7).has_value());  // not held: ignored
  while (grasper.grabbed().size() > 1) {
    EXPECT_FALSE(grasper.on_vertex_removed(grasper.grabbed().back()).has_value());
  }
  const std::optional<ReleaseEvent> lost = grasper.on_vertex_removed(grasper.grabbed()[0]);
  ASSERT_TRUE(lost.has_value());
  EXPECT_EQ(lost->reason, ReleaseReason::lost);
  EXPECT_EQ(grasper.phase(), GraspPhase::closed_empty);
  // The resimplify region still covers all five grabbed vertices' rest points.
  for (const int i : held) {
    EXPECT_LE((row3(block.mesh.rest, i) - lost->resimplify.centre).norm(), lost->resimplify.radius);
  }
}

}  // namespace
}  // namespace incise::sim::tools
