// Tests of sim/tools/probe.h: the proxy follows the device in free space, stops at the surface
// when the device goes in, the hand feels the tissue's reaction once balanced, the hand's local
// force model predicts the next step, the contact region, bad input.
// (The push is checked against the block's support reactions at rest: the probe's force is what
// the tissue carries.)

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "contact_fixtures.h"
#include "sim/tools/probe.h"

namespace incise::sim::tools {
namespace {

using contact_testing::ContactBlock;
using contact_testing::message_of;

constexpr Real kTop = 0.01;  // the block's top [m]

ProbeSettings probe_settings(const ContactBlock& block) {
  ProbeSettings settings;
  settings.radius = 0.004;
  settings.coupling_stiffness = 100;
  settings.allowed_penetration = 0.001;
  settings.contact.time_step = block.dt;
  return settings;
}

TEST(Probe, FollowsTheDeviceInFreeSpace) {
  ContactBlock block(Vec3(0.02, 0.02, kTop), Vec3i(4, 4, 2), contact_testing::kSoft,
                     ContactBlock::Clamp::base);
  Probe probe(probe_settings(block), Vec3(0.01, 0.01, 0.03));
  for (const Vec3& d : {Vec3(0.011, 0.012, 0.025), Vec3(-0.02, 0.03, 0.05)}) {
    block.prepare();
    probe.step(d, block.bvh, block.mesh.x, block.mesh.v, block.model->masses(), block.forces);
    EXPECT_EQ(probe.proxy(), d);
    EXPECT_EQ(probe.hand_force(), Vec3::Zero());
    EXPECT_FALSE(probe.contact_region(block.mesh.rest).touching);
    EXPECT_TRUE(probe.hand_force_model().stiffness.isZero(0));
  }
}

// The device is pushed 3 mm below the top of a soft block; the tissue comes to rest.
struct PressedProbe {
  ContactBlock block{Vec3(0.02, 0.02, kTop), Vec3i(6, 6, 3), contact_testing::kSoft,
                     ContactBlock::Clamp::base};
  Probe probe{probe_settings(block), Vec3(0.0103, 0.0098, kTop + 0.006)};
  Vec3 device = Vec3(0.0103, 0.0098, kTop - 0.003);
  Vec3 mean_hand = Vec3::Zero();
  Vec3 mean_support = Vec3::Zero();

  PressedProbe() {
    const Vec3 start = probe.proxy();
    const VecX& m = block.model->masses();
    const Real c = 0.16 / block.dt;  // mass damping, only to reach rest sooner
    for (int s = 0; s < 900; ++s) {
      const Real t = std::min(1.0, (s + 1) / 200.0);
      block.prepare();
      probe.step(start + t * (device - start), block.bvh, block.mesh.x, block.mesh.v, m,
                 block.forces);
      for (int i = 0; i < block.mesh.num_nodes(); ++i) {
        block.forces.row(i) -= c * m[i] * block.mesh.v.row(i);
      }
      block.integrate();
      // The proxy re-seats on the coarse surface every step (a few % of flicker): average the
      // last 100 steps' hand force and support reaction.
      if (s >= 800) {
        mean_hand += probe.hand_force() / 100;
        mean_support += block.support_reaction() / 100;
      }
    }
    block.mesh.v.setZero();
    // Balance the proxy against the tissue at rest (held).
    for (int s = 0; s < 5; ++s)
      step_held(device);
  }

  void step_held(const Vec3& d) {
    block.prepare();
    probe.step(d, block.bvh, block.mesh.x, block.mesh.v, block.model->masses(), block.forces);
  }
};

TEST(Probe, StopsAtTheSurfaceAndTheHandFeelsTheTissue) {
  PressedProbe pressed;
  const Probe& probe = pressed.probe;
  // The proxy is held out of the tissue (it enters by at most allowed_penetration), far above
  // the device.
  EXPECT_LE(probe.reaction().max_depth, probe.settings().allowed_penetration * (1 + 1e-9));
  EXPECT_GT(probe.proxy().z(), pressed.device.z() + 0.001);
  // The proxy passes the coupling force on to the tissue, and at rest the base holds the block
  // with what the hand pushes (its balance).
  const Vec3 hand = probe.hand_force();
  ASSERT_GT(hand.z(), 0);
  EXPECT_LT((probe.transmitted_force() + hand).norm(), 1e-3 * hand.norm());
  // Pushed straight down, the hand feels mostly an upward force; the side part comes from the
  // coarse mesh's lopsided dimple (20% here on 3.3 mm cells, 1.5% on 1.7 mm cells).
  EXPECT_LT(hand.head<2>().norm(), 0.25 * hand.z());
  EXPECT_LT((pressed.mean_support - pressed.mean_hand).norm(), 0.05 * pressed.mean_hand.norm())
      << pressed.mean_support.transpose() << " vs " << pressed.mean_hand.transpose();
}

// A device driven far into the tissue (a violent hand): the push and the hand force stop at
// max_force, and the tissue stays finite.
TEST(Probe, CouplingSaturatesAtItsMaximumForce) {
  ContactBlock block{Vec3(0.02, 0.02, kTop), Vec3i(6, 6, 3), contact_testing::kSoft,
                     ContactBlock::Clamp::base};
  ProbeSettings settings = probe_settings(block);
  settings.max_force = 0.05;
  Probe probe(settings, Vec3(0.0103, 0.0098, kTop + 0.006));
  const Vec3 deep(0.0103, 0.0098, kTop - 0.02);  // 2 cm below the top: 2 N unsaturated
  int saturated_steps = 0;
  for (int s = 0; s < 300; ++s) {
    block.prepare();
    probe.step(deep, block.bvh, block.mesh.x, block.mesh.v, block.model->masses(), block.forces);
    EXPECT_LE(probe.hand_force().norm(), settings.max_force * (1 + 1e-12)) << "step " << s;
    EXPECT_LE(probe.transmitted_force().norm(), settings.max_force * (1 + 1e-12)) << "step " << s;
    if (std::abs(probe.hand_force().norm() - settings.max_force) < 1e-9) {
      ++saturated_steps;
      EXPECT_TRUE(probe.hand_force_model().stiffness.isZero(0)) << "step " << s;
    }
    block.integrate();
    ASSERT_TRUE(block.mesh.x.allFinite()) << "step " << s;
  }
  // The push passes on less while the tissue gives way; the cap was reached.
  EXPECT_GT(saturated_steps, 0);
  // Pressed at max_force for 300 steps towards a point under the block, the proxy stays on the
  // top: it never slips through (only an enclosed proxy, or one pulled back along its shaft,
  // does).
  EXPECT_EQ(probe.slips(), 0);
  EXPECT_GT(probe.proxy().z(), kTop);
}

// A proxy the tissue has closed over (here it starts inside the block, as after a flap or a
// crack shut over it) cannot sweep out; pulled on at max_force with the device clear of the
// tissue for kTrappedSteps steps, it slips out to the device.
TEST(Probe, ATrappedProxySlipsOutToTheDevice) {
  ContactBlock block{Vec3(0.02, 0.02, kTop), Vec3i(6, 6, 3), contact_testing::kSoft,
                     ContactBlock::Clamp::base};
  ProbeSettings settings = probe_settings(block);
  settings.radius = 0.003;
  settings.max_force = 0.2;
  Probe probe(settings, Vec3(0.01, 0.01, 0.006));  // inside, 4 mm under the top
  const Vec3 away(0.01, 0.01, kTop + 0.03);
  int steps = 0;
  for (; steps < 3 * Probe::kTrappedSteps && probe.slips() == 0; ++steps) {
    block.prepare();
    probe.step(away, block.bvh, block.mesh.x, block.mesh.v, block.model->masses(), block.forces);
    block.integrate();
    ASSERT_TRUE(block.mesh.x.allFinite());
  }
  EXPECT_EQ(probe.slips(), 1);
  EXPECT_EQ(steps, Probe::kTrappedSteps);
  EXPECT_EQ(probe.proxy(), away);
  block.prepare();
  probe.step(away, block.bvh, block.mesh.x, block.mesh.v, block.model->masses(), block.forces);
  EXPECT_EQ(probe.hand_force(), Vec3::Zero());
}

// A proxy on the far side of the tissue from the hand (here under a block whose base is held, the
// device above it): tissue that came between the tip and the hand would have closed over the
// tool's shaft, which the proxy does not model. Pulled back along its shaft at max_force for
// kWithdrawnTime, the tip slips free; without a shaft, with the hand pushing the tip forward
// through the block, or pulling across the shaft, it stays on the surface (no tunnelling).
TEST(Probe, ATipPulledBackAlongItsShaftSlipsFree) {
  struct Case {
    Vec3 shaft;
    int slips;
  };
  for (const Case& c : {Case{Vec3(0, 0, 2), 1}, Case{Vec3(0.5, 0, 1), 1}, Case{Vec3::Zero(), 0},
                        Case{Vec3(0, 0, -1), 0}, Case{Vec3(1, 0, 0), 0}}) {
    ContactBlock block{Vec3(0.02, 0.02, kTop), Vec3i(6, 6, 3), contact_testing::kSoft,
                       ContactBlock::Clamp::base};
    ProbeSettings settings = probe_settings(block);
    settings.radius = 0.003;
    settings.max_force = 0.2;
    Probe probe(settings, Vec3(0.01, 0.01, -0.004));  // under the block, clear of it
    probe.set_shaft(c.shaft);
    const Vec3 above(0.01, 0.01, kTop + 0.03);
    const int withdrawn_steps = static_cast<int>(std::ceil(Probe::kWithdrawnTime / block.dt));
    int steps = 0;
    for (; steps < 3 * withdrawn_steps && probe.slips() == 0; ++steps) {
      block.prepare();
      probe.step(above, block.bvh, block.mesh.x, block.mesh.v, block.model->masses(), block.forces);
      block.integrate();
      ASSERT_TRUE(block.mesh.x.allFinite());
    }
    const std::string shaft = "shaft " + std::to_string(c.shaft.x()) + " " +
                              std::to_string(c.shaft.y()) + " " + std::to_string(c.shaft.z());
    EXPECT_EQ(probe.slips(), c.slips) << shaft;
    if (c.slips > 0) {
      // The pull saturates in the first steps; the slip follows kWithdrawnTime later.
      EXPECT_GE(steps, withdrawn_steps) << shaft;
      EXPECT_LE(steps, withdrawn_steps + 3) << shaft;
      EXPECT_EQ(probe.proxy(), above) << shaft;
    } else {
      EXPECT_LT(probe.proxy().z(), 0) << shaft;  // still under the block
      EXPECT_NEAR(probe.hand_force().norm(), settings.max_force, 1e-9) << shaft;
    }
  }
}

TEST(Probe, ShaftMustBeFinite) {
  ContactBlock block{Vec3(0.02, 0.02, kTop), Vec3i(2, 2, 1), contact_testing::kSoft,
                     ContactBlock::Clamp::base};
  Probe probe(probe_settings(block), Vec3(0.01, 0.01, 0.03));
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_THROW(probe.set_shaft(Vec3(0, nan, 1)), std::invalid_argument);
}

TEST(Probe, HandModelPredictsTheNextStep) {
  PressedProbe pressed;
  const LocalForceModel model = pressed.probe.hand_force_model();
  const Vec3 probe_proxy = pressed.probe.proxy();
  const Real kv = pressed.probe.settings().coupling_stiffness;
  EXPECT_EQ(model.reference_position, pressed.device);
  EXPECT_LT((model.force - pressed.probe.hand_force()).norm(), 1e-12);
  EXPECT_LT((model.stiffness - model.stiffness.transpose()).norm(), 1e-12 * kv);
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(model.stiffness);
  EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-9 * kv);
  // The coupling in series with the contacts over a step: below k_v, near it down (the contacts
  // are 20 times stiffer than the coupling, the light nodes give a little within the step).
  EXPECT_LE(eigen.eigenvalues()[2], kv * (1 + 1e-9));
  EXPECT_GT(eigen.eigenvalues()[2], 0.5 * kv);
  EXPECT_GT(model.stiffness(2, 2), 0.5 * kv);
  // Pressing the hand 0.1 mm deeper, the tissue held: the coupling spring's force k_v (p - d)
  // changes as the model says along the press to 5% of k_v |press|; sideways the proxy re-seats
  // in the coarse dimple (the contacts' normals turn as it moves), which a linear model cannot
  // say: 15% in all.
  const Vec3 press(0, 0, -0.0001);
  pressed.step_held(pressed.device + press);
  const Vec3 predicted = model.force_at(pressed.device + press);
  const Vec3 spring = kv * (pressed.probe.proxy() - pressed.probe.device());
  const Vec3 before = kv * (probe_proxy - pressed.device);
  const Vec3 error = spring - predicted - (before - model.force);
  EXPECT_LT(std::abs(error.z()), 0.05 * kv * press.norm());
  EXPECT_LT(error.norm(), 0.15 * kv * press.norm())
      << spring.transpose() << " vs " << predicted.transpose();
}

TEST(Probe, ReportsTheContactRegionInTheRestConfiguration) {
  PressedProbe pressed;
  const ContactRegion region = pressed.probe.contact_region(pressed.block.mesh.rest);
  ASSERT_TRUE(region.touching);
  // Under the probe, on the undeformed top.
  EXPECT_NEAR(region.centre.z(), kTop, 1e-12);
  EXPECT_LT((region.centre.head<2>() - pressed.device.head<2>()).norm(), 0.002);
  EXPECT_GE(region.radius, pressed.probe.settings().radius);
  EXPECT_LT(region.radius, 3 * pressed.probe.settings().radius);
  EXPECT_THROW(pressed.probe.contact_region(Points::Zero(2, 3)), std::invalid_argument);
}

TEST(Probe, BadInputIsRefusedWithAPreciseMessage) {
  ContactBlock block(Vec3(0.02, 0.02, kTop), Vec3i(2, 2, 1), contact_testing::kSoft,
                     ContactBlock::Clamp::base);
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  ProbeSettings settings = probe_settings(block);
  settings.radius = -0.004;
  EXPECT_EQ(message_of([&] { Probe(settings, Vec3::Zero()); }),
            "Probe: tool radius must be finite and > 0, got -0.004000");
  settings = probe_settings(block);
  settings.allowed_penetration = 0.004;
  EXPECT_EQ(message_of([&] { Probe(settings, Vec3::Zero()); }),
            "Probe: allowed_penetration must be in (0, radius = 0.004000), got "
            "0.004000");
  settings = probe_settings(block);
  settings.coupling_stiffness = 0;
  EXPECT_EQ(message_of([&] { Probe(settings, Vec3::Zero()); }),
            "Probe: coupling_stiffness must be finite and > 0, got 0.000000");
  EXPECT_EQ(message_of([&] { Probe(probe_settings(block), Vec3(nan, 0, 0)); }),
            "Probe: position must be finite, got (nan, 0, 0)");
  Probe probe(probe_settings(block), Vec3(0.01, 0.01, 0.02));
  EXPECT_EQ(message_of([&] {
              probe.step(Vec3(0, 0, nan), block.bvh, block.mesh.x, block.mesh.v,
                         block.model->masses(), block.forces);
            }),
            "Probe::step: device_position must be finite, got (0, 0, nan)");
  EXPECT_EQ(message_of([&] {
              SweptToolMotion(0.002, 0.001)
                  .move(block.bvh, block.mesh.x, Vec3::Zero(), Vec3(0, std::nan(""), 0));
            }),
            "SweptToolMotion::move: to must be finite, got (0, nan, 0)");
}

}  // namespace
}  // namespace incise::sim::tools
