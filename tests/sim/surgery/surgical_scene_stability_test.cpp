// The stability suite at CI size (the long run is surgery_stability): the sequence generator is
// deterministic, bounded (no jump beyond max_jerk, no sweep beyond max_speed) and exercises every
// segment; the player lands on each move's end; a few sequences per scene run with the scalpel
// cutting and the grasper grabbing, and leave no NaN, no inverted element, a bounded mesh; a bad
// input is caught as a failure with its seed.

#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "stability_suite.h"

namespace incise::sim::surgery::stability {
namespace {

// The scenes, built once per process and only when a test needs them (ctest runs each test in
// its own process; the knee takes ~3 s to build).
const SurgicalSceneSetup& liver() {
  static const SurgicalSceneSetup setup = stability_scene("liver");
  return setup;
}
const SurgicalSceneSetup& knee() {
  static const SurgicalSceneSetup setup = stability_scene("knee");
  return setup;
}

TEST(StabilitySuite, SequencesAreDeterministicAndCoverTheirLength) {
  const SceneGeometry g = geometry_of(liver());
  ASSERT_EQ(g.tools.size(), 3u);
  EXPECT_EQ(g.tools[2], ToolKind::scalpel);
  GeneratorSettings settings;
  settings.steps = 800;
  const Sequence a = make_sequence(g, 42, settings);
  const Sequence b = make_sequence(g, 42, settings);
  const Sequence c = make_sequence(g, 43, settings);
  ASSERT_EQ(a.devices.size(), 3u);
  for (std::size_t d = 0; d < a.devices.size(); ++d) {
    ASSERT_EQ(a.devices[d].moves.size(), b.devices[d].moves.size());
    long steps = 0;
    for (std::size_t m = 0; m < a.devices[d].moves.size(); ++m) {
      EXPECT_EQ(a.devices[d].moves[m].tip, b.devices[d].moves[m].tip);
      EXPECT_EQ(a.devices[d].moves[m].steps, b.devices[d].moves[m].steps);
      steps += a.devices[d].moves[m].steps;
    }
    EXPECT_GE(steps, settings.steps) << "device " << d;
  }
  EXPECT_NE(a.devices[0].moves.front().tip, c.devices[0].moves.front().tip);
  settings.steps = 0;
  EXPECT_THROW(make_sequence(g, 1, settings), std::invalid_argument);
  EXPECT_THROW(stability_scene("spleen"), std::invalid_argument);
}

// Per step, a tip moves at most max_speed dt on a move (a move's steps are rounded up) or jumps
// at most max_jerk, and the jaw stays in [0, 1]; a move ends exactly at its tip. Over a few seeds
// every segment a tool is meant for occurs.
void expect_bounded(const SurgicalSceneSetup& setup) {
  const SceneGeometry g = geometry_of(setup);
  GeneratorSettings settings = default_generator(g.name);
  settings.steps = 3000;
  std::array<int, kSegmentKinds> seen{};
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const Sequence s = make_sequence(g, seed, settings);
    for (const DeviceScript& script : s.devices) {
      for (const SegmentKind k : script.segments)
        ++seen[static_cast<std::size_t>(k)];
      // What is played: the first settings.steps steps.
      ScriptPlayer player(script);
      Vec3 previous = script.start.tip;
      int played = 0;
      for (const Move& m : script.moves) {
        for (int k = 0; k < m.steps && played < settings.steps; ++k, ++played) {
          const ToolInput in = player.next();
          const Real moved = (in.tip - previous).norm();
          if (m.jump) {
            EXPECT_LE(moved, settings.max_jerk * (1 + 1e-9));
          } else {
            EXPECT_LE(moved, settings.max_speed * g.dt * (1 + 1e-9)) << g.name << " seed " << seed;
          }
          EXPECT_GE(in.jaw, 0);
          EXPECT_LE(in.jaw, 1);
          previous = in.tip;
        }
        if (played == settings.steps) break;
        EXPECT_LT((previous - m.tip).norm(), 1e-12);
      }
    }
  }
  for (int k = 0; k < kSegmentKinds; ++k) {
    const auto kind = static_cast<SegmentKind>(k);
    if (kind == SegmentKind::grasp && g.name == "knee") continue;  // no grasper in the knee
    EXPECT_GT(seen[static_cast<std::size_t>(k)], 0) << g.name << " " << to_string(kind);
  }
}

TEST(StabilitySuite, PlayedLiverScriptsStayWithinTheirBounds) {
  expect_bounded(liver());
}

// Full sequences per scene: the tools did their work (cuts; a grab in the liver, a bone
// collision in the knee) and the tissue came through: finite, no inversion left, the mesh
// bounded. surgery_stability runs many more; SeedsThatOnceFailedNowPass below keeps the seeds
// that failed before the fixes.
void expect_sound(const SurgicalSceneSetup& setup, const std::vector<std::uint64_t>& seeds) {
  const SceneGeometry g = geometry_of(setup);
  const GeneratorSettings settings = default_generator(g.name);
  const RunSettings run;
  std::array<long, kEventKinds> events{};
  for (const std::uint64_t seed : seeds) {
    const SequenceResult r =
        run_sequence(setup.spec, g.name, make_sequence(g, seed, settings), run);
    EXPECT_TRUE(r.passed) << g.name << " seed " << seed << ": " << r.failure;
    EXPECT_EQ(r.steps, settings.steps);
    EXPECT_EQ(r.inverted_at_end, 0);
    EXPECT_LE(r.peak_tets, run.max_growth * r.initial_tets);
    EXPECT_TRUE(std::isfinite(r.speed_at_end));
    for (int k = 0; k < kEventKinds; ++k)
      events[static_cast<std::size_t>(k)] += r.events[static_cast<std::size_t>(k)];
  }
  EXPECT_GT(events[static_cast<std::size_t>(EventKind::cut)], 0) << g.name;
  if (g.name == "liver") {
    EXPECT_GT(events[static_cast<std::size_t>(EventKind::grasp)], 0);
  } else {
    EXPECT_GT(events[static_cast<std::size_t>(EventKind::collision)], 0);
  }
}

TEST(StabilitySuite, LiverSequencesLeaveTheTissueSound) {
  expect_sound(liver(), {22, 84});
  EXPECT_GT(resident_kib(), 0);
}

// The knee's scripts and sequences in one test: its scene takes ~3 s to build.
TEST(StabilitySuite, KneeScriptsAreBoundedAndSequencesLeaveTheTissueSound) {
  expect_bounded(knee());
  expect_sound(knee(), {20});
}

// Seeds that failed before the runtime's fixes of 2026-11-22 (docs/surgery_stability.md, "The
// fixes"): liver 1 (a grasped node renumbered by a cut), 2 (an open stroke refused for ever), 4
// and 6 (divergence after cuts), 9 and 44 (the organ swinging and tangling after jerks), knee 23
// (mass scales of 3.6e10 after cuts). And the residual class, tissue left inside out until the
// recovery of 2026-11-29 (SurgicalScene::inverted_tets_pulled): liver 6 (since runtime 3's
// round-off, 44 tets) and 4102 (272 tets swinging at up to 4 m/s through the settle), knee 97
// (6 tets) and 244 (one sliver held flat against a bone, which a gentle pull never turned). Each
// must now pass; the residual seeds by recovering. Runtime 6's: knee 40 and 1476 (the scope's tip
// held behind the tissue at 4 N when drawn out, the tangle beside it never pulled: it slips free
// now, tools::Probe::set_shaft, and the tissue relaxes by itself), knee 1402 (a stroke through a
// tangle split 656 tets into 16,760: the cut waits now, cut::tangled_near) and liver 5520.
TEST(StabilitySuite, SeedsThatOnceFailedNowPass) {
  const SceneGeometry g = geometry_of(liver());
  for (const std::uint64_t seed : {1, 2, 4, 6, 9, 44, 4102, 5520}) {
    const SequenceResult r = run_sequence(
        liver().spec, g.name, make_sequence(g, seed, default_generator("liver")), RunSettings{});
    EXPECT_TRUE(r.passed) << "liver seed " << seed << ": " << r.failure;
    EXPECT_EQ(r.inverted_at_end, 0) << "liver seed " << seed;
    if (seed == 6 || seed == 4102) {
      EXPECT_GT(r.inverted_tets_pulled, 0) << "liver seed " << seed;
    }
  }
  const SceneGeometry k = geometry_of(knee());
  for (const std::uint64_t seed : {23, 97, 244, 40, 1476, 1402}) {
    const SequenceResult r = run_sequence(
        knee().spec, k.name, make_sequence(k, seed, default_generator("knee")), RunSettings{});
    EXPECT_TRUE(r.passed) << "knee seed " << seed << ": " << r.failure;
    if (seed == 1402) {
      EXPECT_GT(r.cuts_refused, 0) << "knee seed " << seed;
    } else if (seed == 97 || seed == 244) {
      EXPECT_GT(r.inverted_tets_pulled, 0) << "knee seed " << seed;
    }
  }
}

// A sequence whose input goes non-finite mid-way: the scene throws, the runner reports it as a
// failure at that step, with the seed, and does not throw.
TEST(StabilitySuite, AFailureIsReportedWithItsSeedAndStep) {
  const SceneGeometry g = geometry_of(liver());
  GeneratorSettings settings;
  settings.steps = 50;
  Sequence s = make_sequence(g, 5, settings);
  DeviceScript& probe = s.devices[0];
  probe.moves.insert(probe.moves.begin(), {20, probe.start.tip, probe.start.orientation, 1, false});
  probe.moves.insert(probe.moves.begin() + 1,
                     {1, Vec3::Constant(std::numeric_limits<Real>::quiet_NaN()),
                      probe.start.orientation, 1, true});
  const SequenceResult r = run_sequence(liver().spec, g.name, s, RunSettings{});
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.seed, 5u);
  EXPECT_EQ(r.steps, 20);
  EXPECT_NE(r.failure.find("sequence step 20"), std::string::npos) << r.failure;
  EXPECT_NE(r.failure.find("not finite"), std::string::npos) << r.failure;
}

}  // namespace
}  // namespace incise::sim::surgery::stability
