// The deterministic session core: server/live/sim_engine.h, on the real palpation scene.
#include "server/live/sim_engine.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/scene/scene_error.h"
#include "test_scene.h"

namespace incise::server::live {
namespace {

using test::kCentreXY;
using test::kTickS;
using test::kToolRadius;
using test::kTopZ;

const double kStrainThreshold = sim::surgery::BlockSceneOptions{}.strain_threshold;

devices::DeviceState at(double x, double y, double z) {
  devices::DeviceState s;
  s.position = {x, y, z};
  return s;
}

void run_script(SimEngine& engine, std::int64_t until_tick) {
  while (engine.ticks() < until_tick)
    engine.tick(test::scripted_input(engine.ticks()));
}

TEST(SimEngine, TheTickIsTheFewestStepsNoLongerThanTheScenesStep) {
  const auto scene = test::palpation_scene();  // solver.dt = 2.5e-4 s
  EXPECT_EQ(SimEngine(scene, 0.002).substeps(), 8);
  EXPECT_EQ(SimEngine(scene, 0.001).substeps(), 4);
  EXPECT_EQ(SimEngine(scene, 2.5e-4).substeps(), 1);
  EXPECT_EQ(SimEngine(scene, 0.0021).substeps(), 9);  // steps of 233 us
  EXPECT_EQ(SimEngine(scene, 5e-5).substeps(), 1);
  for (const double bad : {0.0, -0.002, std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_THROW(SimEngine(scene, bad), std::invalid_argument) << bad;
  }
}

TEST(SimEngine, InvalidSceneThrowsSceneError) {
  auto scene = test::palpation_scene();
  scene.material.youngs_modulus = -3;
  EXPECT_THROW(SimEngine(scene, kTickS), sim::SceneError);
}

TEST(SimEngine, StartsAtRestWithTheToolParked) {
  const SimEngine engine(test::palpation_scene(), kTickS);
  EXPECT_EQ(engine.ticks(), 0);
  EXPECT_EQ(engine.time_s(), 0.0);
  EXPECT_EQ(engine.tool_tip(), sim::Vec3(0, 0, kParkedToolHeight));
  EXPECT_EQ(engine.tool_radius(), kToolRadius);
  EXPECT_EQ(engine.contact().nodes_in_contact, 0);
  EXPECT_TRUE(test::same_bits(engine.world().scene().tissue().mesh().x,
                              engine.world().scene().tissue().mesh().rest));
}

TEST(SimEngine, SameInputsGiveTheSameStateBitForBit) {
  const auto scene = test::palpation_scene();
  SimEngine a(scene, kTickS);
  SimEngine b(scene, kTickS);
  const auto initial = a.state_hash();
  EXPECT_EQ(initial, b.state_hash());
  run_script(a, 300);
  run_script(b, 300);
  EXPECT_EQ(a.ticks(), 300);
  EXPECT_DOUBLE_EQ(a.time_s(), 0.6);
  EXPECT_GT(a.metrics().contact_ticks, 0);  // the script did touch the tissue
  EXPECT_EQ(a.state_hash(), b.state_hash());
  EXPECT_TRUE(
      test::same_bits(a.world().scene().tissue().mesh().x, b.world().scene().tissue().mesh().x));
  EXPECT_NE(a.state_hash(), initial);
  ASSERT_EQ(a.state_hash().size(), 16u);

  // One different input (a tenth of a millimetre at one tick in contact) changes the state.
  SimEngine c(scene, kTickS);
  while (c.ticks() < 300) {
    auto input = test::scripted_input(c.ticks());
    if (c.ticks() == 200) input.position.z -= 1e-4;
    c.tick(input);
  }
  EXPECT_NE(c.state_hash(), a.state_hash());
}

// FNV-1a 64 with the published constants.
std::string fnv1a_64(const unsigned char* bytes, std::size_t size) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::size_t i = 0; i < size; ++i) {
    h ^= bytes[i];
    h *= 0x100000001b3ull;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

TEST(SimEngine, StateHashIsFnv1a64OfThePositionBytes) {
  SimEngine engine(test::palpation_scene(), kTickS);
  run_script(engine, 20);
  const auto& x = engine.world().scene().tissue().mesh().x;
  EXPECT_EQ(engine.state_hash(), fnv1a_64(reinterpret_cast<const unsigned char*>(x.data()),
                                          static_cast<std::size_t>(x.size()) * sizeof(double)));
}

TEST(SimEngine, RestoringACheckpointReproducesTheRun) {
  const auto scene = test::palpation_scene();
  SimEngine engine(scene, kTickS);
  run_script(engine, 150);
  const auto checkpoint = engine.checkpoint();
  const auto hash_at_checkpoint = engine.state_hash();
  run_script(engine, 300);
  const auto hash = engine.state_hash();
  const auto x = engine.world().scene().tissue().mesh().x;
  const auto metrics = engine.metrics();
  const auto tip = engine.tool_tip();
  const auto force = engine.contact().force_on_tool;
  const double damage = engine.damage_index();
  const double peak_strain = engine.peak_strain();
  ASSERT_GT(peak_strain, 0);  // the script dips into the tissue

  engine.restore(checkpoint);
  EXPECT_EQ(engine.ticks(), 150);
  EXPECT_EQ(engine.state_hash(), hash_at_checkpoint);
  run_script(engine, 300);
  EXPECT_EQ(engine.state_hash(), hash);
  EXPECT_TRUE(test::same_bits(engine.world().scene().tissue().mesh().x, x));
  EXPECT_EQ(engine.tool_tip(), tip);
  EXPECT_EQ(engine.contact().force_on_tool, force);
  EXPECT_EQ(engine.metrics().path_length_m, metrics.path_length_m);
  EXPECT_EQ(engine.metrics().peak_force_n, metrics.peak_force_n);
  EXPECT_EQ(engine.metrics().force_squared_time, metrics.force_squared_time);
  EXPECT_EQ(engine.metrics().contact_ticks, metrics.contact_ticks);
  EXPECT_EQ(engine.damage_index(), damage);
  EXPECT_EQ(engine.peak_strain(), peak_strain);

  // A checkpoint also carries over to another engine of the same scene.
  SimEngine other(scene, kTickS);
  other.restore(checkpoint);
  run_script(other, 300);
  EXPECT_EQ(other.state_hash(), hash);
}

TEST(SimEngine, PressingTheTopFacePushesTheToolUp) {
  SimEngine engine(test::palpation_scene(), kTickS);
  // Lower the probe onto the top node at the block's centre from 1 cm above contact to 6 mm
  // below it over 0.4 s, then hold it there for 0.2 s.
  const double z_touch = kTopZ + kToolRadius;
  for (int i = 0; i <= 200; ++i) {
    engine.tick(at(kCentreXY, kCentreXY, z_touch + 0.01 - 0.016 * i / 200.0));
  }
  for (int i = 0; i < 100; ++i)
    engine.tick(at(kCentreXY, kCentreXY, z_touch - 0.006));

  const auto& contact = engine.contact();
  ASSERT_GT(contact.nodes_in_contact, 0);
  const sim::Vec3 f = contact.force_on_tool;
  EXPECT_GT(f.z(), 0);
  EXPECT_GT(f.z(), 0.9 * f.norm());            // pressing straight down: the reaction points up
  EXPECT_LT(f.norm(), SimEngine::kMaxForceN);  // so the force model carries it unclamped

  const auto model = engine.force_model();
  EXPECT_EQ(model.force, (devices::Vec3{f.x(), f.y(), f.z()}));
  EXPECT_EQ(model.reference_position, (devices::Vec3{kCentreXY, kCentreXY, z_touch - 0.006}));
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(model.stiffness[static_cast<std::size_t>(3 * r + c)], contact.stiffness(r, c));
  EXPECT_GT(model.stiffness[8], 0);  // pushing further down would push back harder
  EXPECT_EQ(model.sim_time_s, engine.time_s());
  EXPECT_DOUBLE_EQ(model.sim_time_s, 301 * kTickS);
}

// An instrument held in the tissue as the session starts (a station's agent plays its script
// from wherever it is when the session begins): the probe enters the scene only once it is clear
// of the tissue. Made inside, its proxy was engulfed, and when the hand drew back it held it at up
// to the coupling's full force (10 to 15 N on the palpation block, where a press carries 0.2 N).
// Started pressed 8 mm in (the tip's sphere through the top face, its centre 3 mm under it,
// deeper than the block sags under gravity) or 15 mm in (the whole sphere inside: only the ray's
// parity tells), the hand feels nothing until it comes out, feels nothing above the block, and
// then feels what a hand that started above feels pressing as deep.
TEST(SimEngine, AProbeHeldInTheTissueAsTheSessionStartsEntersItFromOutside) {
  const double z_touch = kTopZ + kToolRadius;
  const double above = z_touch + 0.02, pressed = z_touch - 0.008;
  const auto move = [](SimEngine& engine, double z0, double z1, int ticks) {
    for (int i = 1; i <= ticks; ++i)
      engine.tick(at(kCentreXY, kCentreXY, z0 + (z1 - z0) * i / ticks));
  };
  SimEngine from_above(test::palpation_scene(), kTickS);
  move(from_above, above, above, 50);
  move(from_above, above, pressed, 500);
  move(from_above, pressed, pressed, 500);
  const sim::Vec3 reference = from_above.contact().force_on_tool;
  ASSERT_GT(reference.z(), 0.05);

  for (const double start : {pressed, kTopZ - 0.015}) {
    SimEngine held_in(test::palpation_scene(), kTickS);
    move(held_in, start, start, 250);
    EXPECT_EQ(held_in.contact().force_on_tool, sim::Vec3::Zero()) << start;
    EXPECT_EQ(held_in.contact().nodes_in_contact, 0) << start;
    move(held_in, start, above, 500);
    move(held_in, above, above, 50);
    EXPECT_EQ(held_in.contact().nodes_in_contact, 0) << start;
    EXPECT_LT(held_in.contact().force_on_tool.norm(), 1e-9) << start;
    EXPECT_LT(held_in.metrics().peak_force_n, 2 * reference.norm()) << start;
    move(held_in, above, pressed, 500);
    move(held_in, pressed, pressed, 500);
    const sim::Vec3 felt = held_in.contact().force_on_tool;
    EXPECT_LT((felt - reference).norm(), 0.02 * reference.norm())
        << "started at " << start << ": felt " << felt.transpose() << ", from above "
        << reference.transpose();
  }
}

// A two-handed session's second device reports late: until then the session gives it the park,
// and the scene leaves that hand out. Its first state, pressed into the block, then waits like a
// first hand's would; before, its probe was made at the park and swept in from a metre up onto
// the top face, pushing the hand out with the coupling's force.
TEST(SimEngine, ASecondHandThatFirstReportsInTheTissueEntersItFromOutside) {
  const double z_touch = kTopZ + kToolRadius;
  const double above = z_touch + 0.02, pressed = z_touch - 0.008;
  const std::array<devices::DeviceState, 2> waiting = {at(0.02, 0.02, above),
                                                       at(0, 0, kParkedToolHeight)};
  SimEngine engine(test::palpation_scene(), kTickS, 2);
  for (int i = 0; i < 100; ++i)
    engine.tick(waiting);
  const std::array<devices::DeviceState, 2> reported = {at(0.02, 0.02, above),
                                                        at(kCentreXY, kCentreXY, pressed)};
  for (int i = 0; i < 250; ++i)
    engine.tick(reported);
  EXPECT_EQ(engine.contact(1).force_on_tool, sim::Vec3::Zero());
  EXPECT_EQ(engine.contact(1).nodes_in_contact, 0);
  EXPECT_TRUE(engine.state_finite());
}

// The simulation's damage (sim/tools/damage_tracker.h): a tet strained beyond kStrainThreshold is
// damaged for good. Lowering the probe into the block's centre to a depth d and holding it
// there: no contact, no damage; the deeper the press, the larger the peak strain and the damage;
// damage appears exactly when the peak strain passes the threshold, and stays once the probe is
// lifted away.
TEST(SimEngine, PressingDeepDamagesTheTissueAndTheDamageStays) {
  const double z_touch = kTopZ + kToolRadius;
  std::vector<double> damage;
  std::vector<double> strain;
  for (const double depth : {-0.005, 0.002, 0.008, 0.014}) {
    SCOPED_TRACE(depth);
    SimEngine engine(test::palpation_scene(), kTickS);
    for (int i = 0; i <= 200; ++i)
      engine.tick(at(kCentreXY, kCentreXY, z_touch + 0.01 - (0.01 + depth) * i / 200.0));
    for (int i = 0; i < 150; ++i)
      engine.tick(at(kCentreXY, kCentreXY, z_touch - depth));
    damage.push_back(engine.damage_index());
    strain.push_back(engine.peak_strain());
    EXPECT_EQ(engine.damage_index() > 0, engine.peak_strain() > kStrainThreshold);
    EXPECT_GE(engine.damage_index(), 0);
    EXPECT_LE(engine.damage_index(), 1);
    // Lift the probe well clear: the strain relaxes, the damage never heals (the deep press's
    // rebound may add a little).
    for (int i = 1; i <= 100; ++i)
      engine.tick(at(kCentreXY, kCentreXY, z_touch - depth + (0.02 + depth) * i / 100.0));
    for (int i = 0; i < 150; ++i)
      engine.tick(at(kCentreXY, kCentreXY, z_touch + 0.02));
    EXPECT_GE(engine.damage_index(), damage.back());
    EXPECT_GE(engine.peak_strain(), strain.back());
    EXPECT_EQ(engine.damage_index() > 0, engine.peak_strain() > kStrainThreshold);
  }
  EXPECT_EQ(damage[0], 0);  // never touched
  // Untouched, the block only sags under its weight: strains below rho g h / E = 1000 x 9.81 x
  // 0.03 / 3000 = 0.098, the compression at its base.
  EXPECT_LT(strain[0], 1000 * 9.81 * 0.03 / 3000);
  EXPECT_LT(strain[1], kStrainThreshold);  // a gentle press does no harm
  EXPECT_EQ(damage[1], 0);
  EXPECT_GT(damage[3], 0);  // a deep press does
  for (std::size_t i = 1; i < strain.size(); ++i) {
    EXPECT_GT(strain[i], strain[i - 1]);
    EXPECT_GE(damage[i], damage[i - 1]);
  }
}

// The palpation tissue is far too soft to push back with kMaxForceN, so this uses the palpation
// block with every node fixed and a stiff probe. The probe's proxy then rests on the rigid top
// face while the device is delta below where the tip would touch it: the hand feels the coupling
// k (p - d), and the contacts under the proxy (stiffness 20 k each) carry it, so that
// k delta / (1 + 1 / 20) <= |F| <= k delta, straight up (tools/probe.h).
class FixedBlock : public ::testing::Test {
 protected:
  static constexpr double kStiffness = 1e4;  // [N/m]

  static sim::Scene scene() {
    auto json = nlohmann::json::parse(test::palpation_text());
    json["constraints"] =
        nlohmann::json::array({{{"where", {{"box", {{-1, -1, -1}, {1, 1, 1}}}}}, {"fix", "xyz"}}});
    json["tool"]["stiffness"] = kStiffness;
    return sim::parse_scene(json);
  }

  // The device delta below touching, after a tick above the block (where the proxy is made).
  void press(double delta) {
    engine_.tick(at(kCentreXY, kCentreXY, kTopZ + kToolRadius + 0.002));
    for (int i = 0; i < 5; ++i)
      engine_.tick(at(kCentreXY, kCentreXY, kTopZ + kToolRadius - delta));
  }

  SimEngine engine_{scene(), kTickS};
};

TEST_F(FixedBlock, ForceBelowTheLimitIsPassedOnAsIs) {
  const double delta = 0.0005;  // about 5 N
  press(delta);
  ASSERT_EQ(engine_.contact().nodes_in_contact, 1);
  const sim::Vec3 f = engine_.contact().force_on_tool;
  EXPECT_NEAR(f.x(), 0, 1e-9);
  EXPECT_NEAR(f.y(), 0, 1e-9);
  EXPECT_GE(f.z(), kStiffness * delta / (1 + 1.0 / 20) - 1e-9);
  EXPECT_LE(f.z(), kStiffness * delta + 1e-9);
  EXPECT_EQ(engine_.force_model().force, (devices::Vec3{f.x(), f.y(), f.z()}));
  EXPECT_GT(engine_.force_model().stiffness[8], 0);  // pressing deeper pushes back harder
  EXPECT_EQ(engine_.metrics().peak_force_n, f.norm());
}

TEST_F(FixedBlock, ForceAboveTheLimitIsClampedToItAlongTheSameDirection) {
  // 4 mm below touching: 40 N of coupling, twice the limit. The probe saturates at the session's
  // limit (make_block_surgery), and the engine clamps whatever reaches the device to it.
  press(0.004);
  ASSERT_EQ(engine_.contact().nodes_in_contact, 1);
  const sim::Vec3 f = engine_.contact().force_on_tool;
  EXPECT_NEAR(f.norm(), SimEngine::kMaxForceN, 1e-9);
  EXPECT_NEAR(f.normalized().z(), 1.0, 1e-12);
  const auto model = engine_.force_model();
  const sim::Vec3 clamped(model.force.x, model.force.y, model.force.z);
  EXPECT_LE(clamped.norm(), SimEngine::kMaxForceN);
  EXPECT_NEAR(clamped.normalized().dot(f.normalized()), 1.0, 1e-15);
  // Saturated, the coupling gives no stiffness (pressing deeper does not push back harder).
  for (int k = 0; k < 9; ++k)
    EXPECT_EQ(model.stiffness[static_cast<std::size_t>(k)], 0) << k;
}

TEST(SimEngine, PathLengthOfAStraightLineIsItsLength) {
  SimEngine engine(test::palpation_scene(), kTickS);
  // Well above the tissue, so no contact: 50 inputs evenly along a straight line.
  const sim::Vec3 from(0.01, 0.02, 0.06);
  const sim::Vec3 to(0.07, 0.05, 0.09);
  constexpr int kInputs = 50;
  double sum_of_steps = 0;
  sim::Vec3 previous = from;
  for (int i = 0; i < kInputs; ++i) {
    const sim::Vec3 p = from + (to - from) * (static_cast<double>(i) / (kInputs - 1));
    engine.tick(at(p.x(), p.y(), p.z()));
    sum_of_steps += (p - previous).norm();
    previous = p;
    EXPECT_EQ(engine.tool_tip(), p);
  }
  // The first input places the tool: the path starts there, not at the parking position.
  EXPECT_NEAR(engine.metrics().path_length_m, (to - from).norm(), 1e-15);
  EXPECT_NEAR(engine.metrics().path_length_m, sum_of_steps, 1e-15);
  EXPECT_EQ(engine.metrics().peak_force_n, 0);
  EXPECT_EQ(engine.metrics().force_squared_time, 0);
  EXPECT_EQ(engine.metrics().contact_ticks, 0);
}

TEST(SimEngine, RunningMetricsFollowTheContactForce) {
  SimEngine engine(test::palpation_scene(), kTickS);
  double peak = 0;
  double force_squared_time = 0;
  std::int64_t contact_ticks = 0;
  double path = 0;
  // The script for 0.5 s (one dip into the tissue and out), then 50 ticks held above it.
  for (std::int64_t i = 0; i < 300; ++i) {
    const auto input = i < 250 ? test::scripted_input(i) : test::scripted_input(249);
    const sim::Vec3 before = engine.tool_tip();
    engine.tick(input);
    if (i > 0) path += (engine.tool_tip() - before).norm();
    const double force = engine.contact().force_on_tool.norm();
    peak = std::max(peak, force);
    force_squared_time += force * force * kTickS;
    if (engine.contact().nodes_in_contact > 0) ++contact_ticks;

    const auto& m = engine.metrics();
    ASSERT_GE(m.peak_force_n, force) << "tick " << i;
    ASSERT_EQ(m.peak_force_n, peak) << "tick " << i;
    ASSERT_EQ(m.contact_ticks, contact_ticks) << "tick " << i;
    ASSERT_NEAR(m.force_squared_time, force_squared_time, 1e-12 * force_squared_time);
    ASSERT_NEAR(m.path_length_m, path, 1e-12);
  }
  EXPECT_GT(peak, 0);
  EXPECT_GT(contact_ticks, 0);
  EXPECT_EQ(engine.contact().nodes_in_contact, 0);  // lifted off: now no force, the peak stays
  EXPECT_GT(engine.metrics().peak_force_n, engine.contact().force_on_tool.norm());
}

}  // namespace
}  // namespace incise::server::live
