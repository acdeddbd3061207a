// The arthroscopy station fits together: its agent's portals are the knee scene's, the tour the
// demo agent plays touches every target of the demo's tour task, those targets are the scene's
// landmarks, and the station's step is the mass-scaled one it asks for.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "curriculum/curriculum.h"
#include "curriculum/curriculum_json.h"
#include "devices/eigen_conversions.h"
#include "devices/simulated_scope.h"
#include "server/live/frame_streamer.h"
#include "server/live/scene_library.h"
#include "server/live/session_scene.h"
#include "sim/solve/stable_time_step.h"

namespace incise::server::live {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

const SessionScene& knee_station() {
  static const SessionScene scene = [] {
    const auto source = find_scene("scenes/surgery/knee_station.json");
    if (!source) throw std::runtime_error("no knee station scene");
    return load_session_scene(source->id, source->text);
  }();
  return scene;
}

const sim::Portal& portal(const std::string& name) {
  for (const auto& p : knee_station().setup().portals)
    if (p.name == name) return p;
  throw std::out_of_range("no portal " + name);
}

TEST(KneeStation, TheAgentsPortalsAreTheScenes) {
  for (const bool lateral : {true, false}) {
    const devices::ScopeGeometry g = devices::knee_portal_geometry(lateral);
    const sim::Portal& p = portal(lateral ? "anterolateral" : "anteromedial");
    EXPECT_LT((devices::to_eigen(g.portal) - p.position).norm(), 1e-12) << p.name;
    const Eigen::Vector3d axis = devices::to_eigen(g.portal_orientation) * Eigen::Vector3d::UnitZ();
    EXPECT_LT((axis - p.direction).norm(), 1e-9) << p.name;
  }
}

// The demo agent's probe, through its portal's kinematics, comes within each target's radius of
// every target of the tour task (so the demo passes it), and each target is one of the scene's
// landmarks (so the task asks for what the trainee sees).
TEST(KneeStation, TheDemoTourTouchesEveryTargetAndTheTargetsAreTheKneesLandmarks) {
  const curriculum::Curriculum demo =
      curriculum::parse_curriculum_text(read_text(INCISE_DEMO_CURRICULUM));
  const curriculum::Task* tour = curriculum::find_task(demo, "knee_tour");
  ASSERT_NE(tour, nullptr);
  ASSERT_EQ(tour->targets.size(), 4u);
  for (const curriculum::Zone& target : tour->targets) {
    double nearest = 1;
    for (const auto& l : knee_station().setup().landmarks) {
      const Eigen::Vector3d c(target.center_m[0], target.center_m[1], target.center_m[2]);
      nearest = std::min(nearest, (l.position - c).norm());
    }
    EXPECT_LT(nearest, 1e-4) << target.name;
  }

  auto script = devices::parse_simulated_script(
      read_text(std::string(INCISE_SOURCE_DIR) + "/deploy/agent/knee_probe_tour.json"));
  ASSERT_TRUE(script) << script.error;
  const double period = script.value->waypoints.back().t;
  devices::SimulatedScope probe(std::move(*script.value), devices::knee_portal_geometry(false));
  std::vector<double> closest(tour->targets.size(), 1.0);
  for (double t = 0; t <= period; t += 0.001) {
    const Eigen::Vector3d tip = devices::to_eigen(probe.poll(t).position);
    for (std::size_t k = 0; k < tour->targets.size(); ++k) {
      const auto& c = tour->targets[k].center_m;
      closest[k] = std::min(closest[k], (tip - Eigen::Vector3d(c[0], c[1], c[2])).norm());
    }
  }
  for (std::size_t k = 0; k < tour->targets.size(); ++k)
    EXPECT_LT(closest[k], tour->targets[k].radius_m) << tour->targets[k].name;
}

// The station asks for a 0.2 ms step: the tissue's densities are scaled by (0.2 ms / stable step)^2
// and the step is then the scaled tissue's stable step.
TEST(KneeStation, ItsStepIsTheOneItAsksForByMassScaling) {
  const auto& setup = knee_station().setup();
  EXPECT_NEAR(setup.spec.dt, 2e-4, 1e-12);
  const double c = sim::p_wave_speed(60000, 0.3, 1100);  // the ACL's, the stiffest tissue
  const double stable =
      sim::kExplicitSafety *
      sim::element_lengths(setup.spec.tissue.rest, setup.spec.tissue.tets).min_altitude / c;
  EXPECT_NEAR(setup.mass_scale, (2e-4 / stable) * (2e-4 / stable), 1e-9 * setup.mass_scale);
  EXPECT_GT(setup.mass_scale, 1);
}

// What the arthroscope shows of the knee: each soft tissue in its own look (menisci white, the
// ACL's sheath with vessels, the synovium's vessels), and the tour's four landmarks as the
// trainee's visible targets, where the task puts them.
TEST(KneeStation, ItsTissuesHaveTheirLooksAndTheTourShowsItsLandmarks) {
  const render::SceneStyle style = scene_style(knee_station().setup());
  for (const int label :
       {sim::kMedialMeniscusLabel, sim::kLateralMeniscusLabel, sim::kLigamentLabel}) {
    ASSERT_TRUE(style.tissue_by_label.contains(label)) << label;
    EXPECT_GT(style.tissue_by_label.at(label).albedo.minCoeff(), 0.75f) << label;  // white
    EXPECT_GT(style.tissue_by_label.at(label).vessels, 0.0f) << label;
  }
  EXPECT_GT(style.tissue_by_label.at(sim::kLigamentLabel).vessels,
            style.tissue_by_label.at(sim::kMedialMeniscusLabel).vessels);
  EXPECT_GT(style.lining.vessels, 0.0f);
  EXPECT_EQ(style.bone.vessels, 0.0f);

  const curriculum::Curriculum demo =
      curriculum::parse_curriculum_text(read_text(INCISE_DEMO_CURRICULUM));
  const curriculum::Task* tour = curriculum::find_task(demo, "knee_tour");
  ASSERT_NE(tour, nullptr);
  const std::vector<render::MarkView> zones = task_zones(*tour);
  ASSERT_EQ(zones.size(), tour->targets.size());
  for (std::size_t k = 0; k < zones.size(); ++k) {
    const auto& c = tour->targets[k].center_m;
    EXPECT_EQ(zones[k].kind, render::MarkKind::target);
    EXPECT_EQ(zones[k].centre, Eigen::Vector3d(c[0], c[1], c[2]));
    EXPECT_EQ(zones[k].radius, tour->targets[k].radius_m);
  }
  // Hidden zones are not drawn; a protected zone is amber, a never-zone red.
  curriculum::Task task = *tour;
  task.targets[1].visible = false;
  task.protected_zones = {{{"ACL", {0, 0, 0}, 0.003, true}, false},
                          {{"artery", {0, 0, 0}, 0.003, true}, true},
                          {{"nerve", {0, 0, 0}, 0.003, false}, true}};
  const std::vector<render::MarkView> shown = task_zones(task);
  ASSERT_EQ(shown.size(), 5u);
  EXPECT_EQ(shown[1].centre, zones[2].centre);
  EXPECT_EQ(shown[3].kind, render::MarkKind::protected_zone);
  EXPECT_EQ(shown[4].kind, render::MarkKind::never_zone);
}

}  // namespace
}  // namespace incise::server::live
