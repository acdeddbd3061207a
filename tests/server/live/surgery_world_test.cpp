// A surgical scene hosted by a session's engine (server/live/surgery_world.h, sim_engine.h,
// scene_event_log.h): the liver station scene as the server embeds it, the scalpel on device 0
// and the grasper on device 1 driven tick by tick as a station's devices would drive them.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "server/live/replay_session.h"
#include "server/live/scene_library.h"
#include "server/live/scoring.h"
#include "server/live/session_scene.h"
#include "server/live/sim_engine.h"
#include "server/live/tick_record.h"
#include "tests/server/live/test_scene.h"

namespace incise::server::live {
namespace {

constexpr const char* kLiverId = "scenes/surgery/liver_station.json";
constexpr double kTickS = 0.002;
constexpr double kDepth = 0.006;  // how deep the blade's tip goes below the marked line [m]

// The scene, meshed once for the whole suite (about a second).
const SessionScene& liver() {
  static const SessionScene scene = [] {
    const auto source = find_scene(kLiverId);
    if (!source) throw std::runtime_error("the liver station scene is not embedded");
    return load_session_scene(source->id, source->text);
  }();
  return scene;
}
const sim::surgery::SurgicalSceneSetup& setup() {
  return liver().setup();
}

sim::Vec3 place(const std::string& name) {
  for (const auto& l : setup().landmarks)
    if (l.name == name) return l.position;
  throw std::runtime_error("no landmark " + name);
}

// A tool pointing straight down (R = 180 degrees about x: d = R e_z = -e_z), or up (R = I).
constexpr devices::Quat kDown{0, 1, 0, 0};
constexpr devices::Quat kUp{1, 0, 0, 0};
devices::DeviceState pointing_down(const sim::Vec3& tip, float jaw = 1.0f,
                                   devices::Quat orientation = kDown) {
  devices::DeviceState s;
  s.position = {tip.x(), tip.y(), tip.z()};
  s.orientation = orientation;
  s.jaw = jaw;
  return s;
}
devices::DeviceState parked() {
  devices::DeviceState s;
  s.position = {0, 0, kParkedToolHeight};
  return s;
}

// Hand 0's tip through the given waypoints, `seconds_each` from one to the next, hand 1 parked.
void stroke(SimEngine& engine, const std::vector<sim::Vec3>& waypoints, double seconds_each,
            devices::Quat orientation = kDown) {
  const auto ticks_each = static_cast<int>(seconds_each / kTickS);
  for (std::size_t k = 0; k + 1 < waypoints.size(); ++k) {
    for (int i = 1; i <= ticks_each; ++i) {
      const double a = static_cast<double>(i) / ticks_each;
      const std::array<devices::DeviceState, 2> inputs = {
          pointing_down((1 - a) * waypoints[k] + a * waypoints[k + 1], 1.0f, orientation),
          parked()};
      engine.tick(inputs);
    }
  }
}

// Above the line's start, into the tissue, along the line, out above its end.
std::vector<sim::Vec3> along_the_line() {
  const sim::Vec3 down(0, 0, kDepth);
  const sim::Vec3 up(0, 0, 0.01);
  return {place("cut_start") + up, place("cut_start") - down, place("cut_end") - down,
          place("cut_end") + up};
}

TEST(SurgeryEngine, TheTickIsTheFewestStepsNoLongerThanTheScenesStableStep) {
  const SimEngine engine(liver(), kTickS, 2);
  const int n = engine.substeps();
  ASSERT_GE(n, 1);
  EXPECT_LE(kTickS / n, setup().spec.dt);
  if (n > 1) {
    EXPECT_GT(kTickS / (n - 1), setup().spec.dt);
  }
  EXPECT_EQ(engine.positions().rows(), setup().spec.tissue.rest.rows());
  EXPECT_EQ(engine.surface()->faces.rows(), engine.world().scene().tissue().surface().faces.rows());
  EXPECT_TRUE(engine.state_finite());
  EXPECT_THROW(SimEngine(liver(), 0.0, 2), std::invalid_argument);
  EXPECT_THROW(SimEngine(liver(), kTickS, 3), std::invalid_argument);
}

TEST(SurgeryEngine, AStrokeAlongTheMarkedLineCutsOnTargetAndReplaysBitForBit) {
  SimEngine engine(liver(), kTickS, 2);
  const auto surface_before = engine.surface();
  const auto start = engine.checkpoint();
  stroke(engine, along_the_line(), 0.15);
  ASSERT_TRUE(engine.state_finite());
  const auto damage = engine.damage();
  std::printf("cut %.1f mm^2, %.1f mm^2 off target, mean distance %.2f mm, %d tets\n",
              1e6 * damage.cut_area, 1e6 * damage.cut_area_outside_target,
              1e3 * damage.cut_mean_distance, engine.world().scene().tissue().mesh().num_tets());
  // 4 cm along the line, 6 mm deep: at most 240 mm^2 (docs/surgical_scenes.md: shallow cuts
  // open in part).
  EXPECT_GT(damage.cut_area, 40e-6);
  EXPECT_LT(damage.cut_area, 0.04 * (kDepth + 0.003));
  EXPECT_LE(damage.cut_area_outside_target, 0.1 * damage.cut_area);
  EXPECT_LT(damage.cut_mean_distance, setup().spec.damage.target.half_width);
  EXPECT_FALSE(damage.never_event);
  // The cut changed the tissue's boundary: the renderer gets a new surface.
  EXPECT_NE(engine.surface(), surface_before);
  // Its walls are the faces drawn in the interior's colour: both sides of the cut, so twice its
  // (one-sided, rest) area; before the stroke there were none.
  const auto& walls = *engine.world().cut_faces();
  const sim::BoundarySurface& surface = *engine.surface();
  const sim::Points& rest = engine.world().scene().tissue().mesh().rest;
  ASSERT_EQ(walls.size(), static_cast<std::size_t>(surface.faces.rows()));
  double wall_area = 0;
  for (int f = 0; f < surface.faces.rows(); ++f) {
    if (walls[static_cast<std::size_t>(f)] == 0) continue;
    const auto corner = [&](int k) -> sim::Vec3 {
      return rest.row(surface.nodes[static_cast<std::size_t>(surface.faces(f, k))]).transpose();
    };
    wall_area += 0.5 * (corner(1) - corner(0)).cross(corner(2) - corner(0)).norm();
  }
  EXPECT_NEAR(wall_area, 2 * damage.cut_area, 0.2 * 2 * damage.cut_area);
  // The picture's looks and vessels follow the new surface too: each face's label is its tet's
  // (the liver's and the gallbladder bed's), each vertex's rest position its node's.
  const auto& labels = *engine.world().face_labels();
  const sim::Points& surface_rest = *engine.world().surface_rest();
  const sim::TetMesh& mesh = engine.world().scene().tissue().mesh();
  ASSERT_EQ(labels.size(), surface.tets.size());
  for (std::size_t f = 0; f < labels.size(); ++f)
    ASSERT_EQ(labels[f], mesh.labels[surface.tets[f]]) << f;
  EXPECT_GT(std::count(labels.begin(), labels.end(), sim::kGallbladderBedLabel), 0);
  EXPECT_GT(std::count(labels.begin(), labels.end(), sim::kLiverLabel), 0);
  ASSERT_EQ(surface_rest.rows(), static_cast<Eigen::Index>(surface.nodes.size()));
  for (std::size_t j = 0; j < surface.nodes.size(); ++j)
    ASSERT_EQ(surface_rest.row(static_cast<Eigen::Index>(j)), rest.row(surface.nodes[j])) << j;
  SimEngine fresh(liver(), kTickS, 2);
  const auto& none = *fresh.world().cut_faces();
  EXPECT_EQ(std::count(none.begin(), none.end(), 1), 0);

  // One stroke, one cut event, by the right hand, labelled with the stroke's area.
  const auto& events = engine.scene_events().events();
  const auto cuts = std::count_if(events.begin(), events.end(),
                                  [](const SceneEventRecord& e) { return e.kind == "cut"; });
  EXPECT_EQ(cuts, 1);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front().kind, "cut");
  EXPECT_EQ(events.front().hand, 0);
  char area[32];
  std::snprintf(area, sizeof area, "cut %.1f mm^2", 1e6 * damage.cut_area);
  EXPECT_EQ(events.front().label.rfind(area, 0), 0u) << events.front().label;
  EXPECT_GT(events.front().t_s, 0.15);  // not before the blade reached the tissue

  // The same inputs give the same state, from a second engine and from the restored start.
  const auto hash = engine.state_hash();
  SimEngine again(liver(), kTickS, 2);
  stroke(again, along_the_line(), 0.15);
  EXPECT_EQ(again.state_hash(), hash);
  engine.restore(start);
  EXPECT_EQ(engine.ticks(), 0);
  EXPECT_EQ(engine.damage().cut_area, 0);
  EXPECT_TRUE(engine.scene_events().events().empty());
  stroke(engine, along_the_line(), 0.15);
  EXPECT_EQ(engine.state_hash(), hash);

  // What scoring makes of it.
  const auto metrics = simulation_metrics(engine.damage());
  const auto value = [&](const std::string& key) {
    const auto it = std::find_if(metrics.begin(), metrics.end(),
                                 [&](const curriculum::MetricValue& v) { return v.key == key; });
    return it == metrics.end() ? -1.0 : it->value;
  };
  EXPECT_EQ(value("cut_area_m2"), damage.cut_area);
  EXPECT_DOUBLE_EQ(value("cut_on_target_fraction"),
                   1 - damage.cut_area_outside_target / damage.cut_area);
  EXPECT_EQ(value("sim_never_events"), 0);
}

TEST(SurgeryEngine, ACheckpointMidStrokeRestoresTheWholeSceneBitForBitAnyNumberOfTimes) {
  // Checkpointed with the blade in the tissue and a cut open: tissue, model (warm starts
  // included), cutter, damage and events are all in it.
  const std::vector<sim::Vec3> line = along_the_line();
  const sim::Vec3 halfway = 0.5 * (line[1] + line[2]);
  const std::vector<sim::Vec3> first = {line[0], line[1], halfway};
  const std::vector<sim::Vec3> rest = {halfway, line[2], line[3]};
  SimEngine engine(liver(), kTickS, 2);
  stroke(engine, first, 0.15);
  const std::int64_t ticks = engine.ticks();
  const auto middle = engine.checkpoint();
  const std::string middle_hash = engine.state_hash();
  stroke(engine, rest, 0.15);
  const std::string hash = engine.state_hash();
  const auto events = engine.scene_events().events().size();
  const double area = engine.damage().cut_area;
  ASSERT_GT(area, 0);

  for (int again = 0; again < 2; ++again) {
    engine.restore(middle);
    EXPECT_EQ(engine.ticks(), ticks);
    EXPECT_EQ(engine.state_hash(), middle_hash);
    stroke(engine, rest, 0.15);
    EXPECT_EQ(engine.state_hash(), hash) << "restore " << again;
    EXPECT_EQ(engine.scene_events().events().size(), events);
    EXPECT_EQ(engine.damage().cut_area, area);
  }
  // Another engine of the same scene (a replay's engine from the checkpointer's checkpoint).
  SimEngine other(liver(), kTickS, 2);
  other.restore(middle);
  stroke(other, rest, 0.15);
  EXPECT_EQ(other.state_hash(), hash);
}

TEST(SurgeryEngine, AReplayOfACutSeeksBothWaysOntoTheStraightRunsStatesBitForBit) {
  // The stroke of AStrokeAlongTheMarkedLine..., slower, as a recording: hand 0 cuts, hand 1
  // parked; 900 ticks, so that seeks cross checkpoints.
  std::vector<TickRecord> records;
  const std::vector<sim::Vec3> line = along_the_line();
  const int ticks_each = static_cast<int>(0.6 / kTickS);
  for (std::size_t k = 0; k + 1 < line.size(); ++k) {
    for (int i = 1; i <= ticks_each; ++i) {
      const double a = static_cast<double>(i) / ticks_each;
      TickRecord r;
      r.input = pointing_down((1 - a) * line[k] + a * line[k + 1]);
      r.has_second = true;
      r.second.input = parked();
      records.push_back(r);
    }
  }
  const auto total = static_cast<std::int64_t>(records.size());
  const std::vector<std::int64_t> targets = {total - 10, 40, ReplaySession::kCheckpointTicks + 7,
                                             total / 2, 1};
  std::map<std::int64_t, sim::Points> reference;
  {
    SimEngine engine(liver(), kTickS, 2);
    for (const TickRecord& r : records) {
      replay_tick(engine, r);
      if (std::find(targets.begin(), targets.end(), engine.ticks()) != targets.end())
        reference[engine.ticks()] = engine.positions();
    }
  }
  ReplaySession replay(liver(), kTickS, records);
  replay.start();
  replay.pause();
  for (const std::int64_t tick : targets) {
    replay.seek(static_cast<double>(tick) * kTickS);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (replay.snapshot()->tick != tick && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ASSERT_EQ(replay.snapshot()->tick, tick);
    EXPECT_TRUE(test::same_bits(replay.snapshot()->positions, reference.at(tick)))
        << "seek to tick " << tick;
  }
}

TEST(SurgeryEngine, CuttingIntoTheGallbladderBedIsANeverEvent) {
  SimEngine engine(liver(), kTickS, 2);
  // The gallbladder lies under the right lobe, on the flat side (its bed is the organ's tissue
  // within its radius). A scalpel cuts from the surface its blade crosses: pointing up, in from
  // the flat side 2 cm beside the gallbladder's centre, 6 mm deep, sideways past it, and out.
  const sim::Vec3 gallbladder = place("gallbladder");
  const sim::Vec3 side(0.02, 0, 0);
  const sim::Vec3 in(0, 0, 0.006);
  const sim::Vec3 out(0, 0, -0.01);
  stroke(engine,
         {gallbladder - side + out, gallbladder - side + in, gallbladder + side + in,
          gallbladder + side + out},
         0.3, kUp);
  ASSERT_TRUE(engine.state_finite());
  const auto damage = engine.damage();
  EXPECT_TRUE(damage.never_event);
  EXPECT_GT(damage.protected_cut_area, 0);
  const auto& events = engine.scene_events().events();
  EXPECT_TRUE(std::any_of(events.begin(), events.end(), [](const SceneEventRecord& e) {
    return e.kind == "never_event" && e.hand == 0;
  }));
  const auto metrics = simulation_metrics(damage);
  const auto never = std::find_if(metrics.begin(), metrics.end(),
                                  [](const auto& v) { return v.key == "sim_never_events"; });
  ASSERT_NE(never, metrics.end());
  EXPECT_EQ(never->value, 1);
}

TEST(SurgeryEngine, TheGrasperHoldsTheLiverAndTheLeftHandFeelsItsPull) {
  SimEngine engine(liver(), kTickS, 2);
  // The grasper's jaws laid along the right lobe's top (its axis along +x: R = 90 degrees about
  // y; the hinge 0.5 mm above the surface 5 mm before the cut line's middle), closed, then
  // lifted 1 cm.
  const devices::Quat along_x{std::sqrt(0.5), 0, std::sqrt(0.5), 0};
  const sim::Vec3 top = 0.5 * (place("cut_start") + place("cut_end")) - sim::Vec3(0.005, 0, 0);
  const auto run = [&](const sim::Vec3& from, const sim::Vec3& to, float jaw_from, float jaw_to,
                       double seconds) {
    const auto n = static_cast<int>(seconds / kTickS);
    for (int i = 1; i <= n; ++i) {
      const double a = static_cast<double>(i) / n;
      const std::array<devices::DeviceState, 2> inputs = {
          parked(), pointing_down((1 - a) * from + a * to,
                                  static_cast<float>((1 - a) * jaw_from + a * jaw_to), along_x)};
      engine.tick(inputs);
    }
  };
  // At rest the marked line's ink dots are the scene's marked points.
  const auto line = engine.world().marked_line();
  ASSERT_EQ(line.size(), setup().cut_target.size());
  for (std::size_t k = 0; k < line.size(); ++k)
    EXPECT_EQ(line[k], setup().cut_target[k]);
  const sim::Vec3 above = top + sim::Vec3(0, 0, 0.02);
  const sim::Vec3 on = top + sim::Vec3(0, 0, 0.0005);
  const sim::Vec3 lifted = top + sim::Vec3(0, 0, 0.01);
  run(above, on, 1, 1, 0.1);
  run(on, on, 1, 0, 0.1);
  run(on, lifted, 0, 0, 0.2);
  run(lifted, lifted, 0, 0, 0.1);
  ASSERT_TRUE(engine.state_finite());
  const auto& events = engine.scene_events().events();
  EXPECT_TRUE(std::any_of(events.begin(), events.end(), [](const SceneEventRecord& e) {
    return e.kind == "grasp" && e.hand == 1;
  })) << "nothing grabbed";
  // The lifted tissue pulls the jaws back down; the right hand (parked) feels nothing.
  const sim::Vec3 pull = engine.contact(1).force_on_tool;
  std::printf("pull on the left hand %.3f %.3f %.3f N\n", pull.x(), pull.y(), pull.z());
  EXPECT_LT(pull.z(), -0.01);
  EXPECT_EQ(engine.contact(0).force_on_tool.norm(), 0);
  const auto model = engine.force_model(1);
  EXPECT_EQ(model.device_index, 1);
  EXPECT_NEAR(model.force.z, pull.z(), 1e-12);
  EXPECT_EQ(model.reference_position.z, lifted.z());
  // The tissue under the jaws rose, and the ink dots there with it.
  const auto middle = line.size() / 2;
  EXPECT_GT(engine.world().marked_line()[middle].z(), line[middle].z() + 0.001);
}

// A session behind real time sheds its remeshing first (pace_monitor.h, SimEngine::
// set_shed_level): the grasper closing on the liver at level 2 refines nothing (at level 0 it
// refines under its jaws), and the recording, which carries the level per tick, replays onto the
// shed run's state, not the unshed one's.
TEST(SurgeryEngine, ShedRemeshingIsRecordedPerTickAndReplaysAsItRan) {
  const devices::Quat along_x{std::sqrt(0.5), 0, std::sqrt(0.5), 0};
  const sim::Vec3 top = 0.5 * (place("cut_start") + place("cut_end")) - sim::Vec3(0.005, 0, 0);
  const sim::Vec3 above = top + sim::Vec3(0, 0, 0.02);
  const sim::Vec3 on = top + sim::Vec3(0, 0, 0.0005);
  // The grasper's inputs: down onto the lobe (0.1 s), closing (0.1 s), holding (0.05 s).
  std::vector<devices::DeviceState> left;
  const auto add = [&](const sim::Vec3& from, const sim::Vec3& to, float jaw_from, float jaw_to,
                       double seconds) {
    const auto n = static_cast<int>(seconds / kTickS);
    for (int i = 1; i <= n; ++i) {
      const double a = static_cast<double>(i) / n;
      auto state = pointing_down((1 - a) * from + a * to,
                                 static_cast<float>((1 - a) * jaw_from + a * jaw_to), along_x);
      state.device_index = 1;
      left.push_back(state);
    }
  };
  add(above, on, 1, 1, 0.1);
  add(on, on, 1, 0, 0.1);
  add(on, on, 0, 0, 0.05);
  // Level 2 from the 40th tick on (the pace monitor's climb), or never.
  const auto run = [&](bool shed, std::vector<TickRecord>* records) {
    SimEngine engine(liver(), kTickS, 2);
    for (std::size_t i = 0; i < left.size(); ++i) {
      engine.set_shed_level(shed && i >= 40 ? 2 : 0);
      const std::array<devices::DeviceState, 2> inputs = {parked(), left[i]};
      engine.tick(inputs);
      if (records != nullptr) {
        TickRecord r;
        r.tick = static_cast<std::uint32_t>(i);
        r.shed = static_cast<std::uint8_t>(engine.shed_level());
        r.input = inputs[0];
        r.has_second = true;
        r.second.input = inputs[1];
        records->push_back(r);
      }
    }
    EXPECT_TRUE(engine.state_finite());
    return std::make_pair(engine.world().scene().tissue().mesh().num_tets(), engine.state_hash());
  };
  std::vector<TickRecord> records;
  const auto [shed_tets, shed_hash] = run(true, &records);
  const auto [full_tets, full_hash] = run(false, nullptr);
  const int at_rest = setup().spec.tissue.num_tets();
  std::printf("tets after the grasp: %d unshed, %d shed (%d at rest)\n", full_tets, shed_tets,
              at_rest);
  EXPECT_GT(full_tets, at_rest);
  EXPECT_EQ(shed_tets, at_rest);
  // Through the recording's bytes, as a replay reads them.
  std::vector<std::uint8_t> bytes;
  for (const auto& r : records)
    append_tick_record(r, bytes);
  std::vector<TickRecord> decoded;
  ASSERT_EQ(decode_tick_records(bytes, decoded), "");
  EXPECT_EQ(ReplaySession::final_state_hash(liver(), kTickS, decoded), shed_hash);
  EXPECT_NE(shed_hash, full_hash);
}

TEST(SurgeryEngine, TasksMustNameTheToolsTheSceneGivesEachDevice) {
  EXPECT_EQ(tools_mismatch(liver(), {"scalpel", "grasper"}), "");
  EXPECT_EQ(tools_mismatch(liver(), {"scalpel"}), "");
  EXPECT_EQ(tools_mismatch(liver(), {"probe"}),
            "tools[0] is \"probe\" but the scene gives device 0 a scalpel");
  EXPECT_EQ(tools_mismatch(liver(), {"scalpel", "scope"}),
            "tools[1] is \"scope\" but the scene gives device 1 a grasper");
  // The block's probes stand for any tool.
  const auto palpation = find_scene("scenes/palpation.json");
  ASSERT_TRUE(palpation);
  EXPECT_EQ(tools_mismatch(load_session_scene(palpation->id, palpation->text), {"scalpel"}), "");
}

// The trainee's picture is the laparoscope's: from 8 cm above and in front of the marked line's
// middle, looking at it, its light at its tip.
TEST(SurgeryEngine, TheHeldLaparoscopeLooksAtTheMarkedLinesMiddleWithItsLight) {
  const auto camera = camera_for(liver());
  const sim::Vec3 middle = 0.5 * (setup().cut_target.front() + setup().cut_target.back());
  EXPECT_NEAR((camera.eye - middle).norm(), kLaparoscopeDistance, 1e-12);
  EXPECT_GT((camera.target - camera.eye).normalized().dot((middle - camera.eye).normalized()),
            1 - 1e-12);
  EXPECT_GT(camera.eye.z(), middle.z() + 0.03);
  EXPECT_TRUE(camera.headlight);
  EXPECT_LT(camera.near_m, 0.01);
  EXPECT_GT(camera.far_m, 0.2);
  // A 70-degree diagonal at 4:3: tan(fov_y / 2) times the diagonal over the height (5 / 3).
  EXPECT_NEAR(std::tan(camera.fov_y_deg * std::numbers::pi / 360) * 5 / 3,
              std::tan(35 * std::numbers::pi / 180), 1e-12);
}

TEST(SurgeryEngine, TheOutsideCameraLooksFromAboveHalfwayBetweenTheOrgansCentreAndTheLine) {
  const auto camera = outside_camera_for(liver());
  EXPECT_FALSE(camera.headlight);
  const sim::Vec3 middle = 0.5 * (setup().cut_target.front() + setup().cut_target.back());
  const auto& rest = setup().spec.tissue.rest;
  const sim::Vec3 centre =
      0.5 * (rest.colwise().minCoeff() + rest.colwise().maxCoeff()).transpose();
  EXPECT_LT((camera.target - 0.5 * (centre + middle)).norm(), 1e-12);
  EXPECT_GT(camera.eye.z(), middle.z() + 0.05);
  EXPECT_GT(camera.far_m, (camera.eye - camera.target).norm());
  EXPECT_LT(camera.near_m, (camera.eye - camera.target).norm());
}

}  // namespace
}  // namespace incise::server::live
