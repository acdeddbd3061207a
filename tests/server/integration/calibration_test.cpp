// Tissue calibration on the real server (docs/calibration.md): an admin fits the cube's modulus to
// its example data in a background job, saves it as a named material, a task names it, and the
// task's session runs and replays with it; bad data changes nothing; a running job cancels.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <thread>

#include "live_fixture.h"

namespace incise::server::test {
namespace {

using nlohmann::json;

constexpr const char* kCube = "scenes/calibration/cube.json";

class TissueCalibration : public LiveSession {
 protected:
  // The job's JSON once it has ended (or the last seen after `timeout`).
  json wait_for_job(std::int64_t id, std::chrono::seconds timeout) {
    const auto deadline = Clock::now() + timeout;
    json job;
    while (Clock::now() < deadline) {
      job = as(kAdmin).get("/api/calibration/jobs/" + std::to_string(id)).json();
      const std::string status = job["job"]["status"];
      if (status != "queued" && status != "running") break;
      std::this_thread::sleep_for(100ms);
    }
    return job;
  }

  std::string example() {
    const auto response =
        as(kAdmin).get("/api/calibration/example?scene=scenes%2Fcalibration%2Fcube.json");
    EXPECT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "text/csv; charset=utf-8");
    return response.body;
  }
};

TEST_F(TissueCalibration, AFittedMaterialRunsATasksSessionAndItsReplay) {
  auto& admin = as(kAdmin);
  const auto scenes = admin.get("/api/calibration/scenes").json()["scenes"];
  const auto cube =
      std::find_if(scenes.begin(), scenes.end(), [](const json& s) { return s["id"] == kCube; });
  ASSERT_NE(cube, scenes.end()) << scenes;
  EXPECT_EQ((*cube)["model"], "mss");
  EXPECT_EQ((*cube)["per"], json::array({"label", "node"}));
  EXPECT_TRUE((*cube)["has_example"].get<bool>());
  EXPECT_TRUE(is_error(as(kInstructor).get("/api/calibration/jobs"), 403));

  // A file with a word for a force: refused before anything is queued.
  std::string data = example();
  ASSERT_TRUE(data.starts_with("time_s,contact,x,y,z,dir_x,dir_y,dir_z,force_n\n"));
  std::string bad = data;
  const auto third_line = bad.find('\n', bad.find('\n', bad.find('\n') + 1) + 1);
  bad.replace(bad.rfind(',', third_line) + 1, third_line - bad.rfind(',', third_line) - 1, "abc");
  const auto before = snapshot();
  EXPECT_TRUE(is_error(
      admin.post("/api/calibration/jobs",
                 {{"scene", kCube}, {"method", "lm"}, {"data", bad}, {"data_name", "bad.csv"}}),
      422, "data: line 3: force_n 'abc' is not a number"));
  EXPECT_TRUE(is_error(
      admin.post(
          "/api/calibration/jobs",
          {{"scene", "scenes/surgery/liver_station.json"}, {"method", "lm"}, {"data", data}}),
      422,
      "scene: \"scenes/surgery/liver_station.json\" is not a scene this server can calibrate"));
  // A search too large for one node: CMA-ES over the palpation block's 845 node moduli.
  EXPECT_TRUE(is_error(admin.post("/api/calibration/jobs", {{"scene", "scenes/palpation.json"},
                                                            {"method", "cmaes"},
                                                            {"per", "node"},
                                                            {"data", data}}),
                       422,
                       "per: cmaes fits at most 500 parameters, and this scene has 845 nodes: per "
                       "label, or lm"));
  EXPECT_EQ(snapshot(), before);

  // The example data came from a 3.6 kPa cube; the scene says 2.4 kPa.
  const auto created = admin.post("/api/calibration/jobs", {{"scene", kCube},
                                                            {"method", "lm"},
                                                            {"per", "label"},
                                                            {"budget", 200},
                                                            {"data", data},
                                                            {"data_name", "cube_pushes.csv"}});
  ASSERT_EQ(created.status, 201) << created.body;
  const auto id = created.json()["job"]["id"].get<std::int64_t>();
  EXPECT_EQ(created.json()["job"]["contacts"], 5);
  EXPECT_EQ(created.json()["job"]["samples"], 5 * 201);
  const json done = wait_for_job(id, 120s);
  ASSERT_EQ(done["job"]["status"], "done") << done.dump();
  const json& result = done["result"];
  EXPECT_NEAR(result["material"]["E"].get<double>(), 3600, 3600 * 1e-6) << result["material"];
  EXPECT_EQ(result["material"]["model"], "mss");
  EXPECT_LT(result["calibration"]["misfit"].get<double>(),
            1e-6 * result["calibration"]["start_misfit"].get<double>());
  EXPECT_EQ(result["calibration"]["fits"].size(), 5u);
  EXPECT_GT(done["job"]["progress"]["evaluations"].get<int>(), 0);

  // Saved under a name, once.
  const auto saved = admin.post("/api/materials", {{"job", id}, {"name", "Calibrated cube"}});
  ASSERT_EQ(saved.status, 201) << saved.body;
  EXPECT_NEAR(saved.json()["material"]["E"].get<double>(), 3600, 3600 * 1e-6);
  EXPECT_TRUE(is_error(admin.post("/api/materials", {{"job", id}, {"name", "Calibrated cube"}}),
                       409, "a material named \"Calibrated cube\" exists"));

  // The palpation task names it: an unknown name is refused with its place, the saved one taken.
  const auto curricula = admin.get("/api/curricula").json();
  json definition = curricula[0]["definition"];
  const auto curriculum_id = curricula[0]["id"].get<std::int64_t>();
  ASSERT_EQ(definition["modules"][0]["tasks"][0]["key"], "palpation");
  definition["modules"][0]["tasks"][0]["material"] = "No such tissue";
  EXPECT_TRUE(is_error(admin.put("/api/curricula/" + std::to_string(curriculum_id), definition),
                       422,
                       "modules[0].tasks[0].material: material \"No such tissue\", which does not "
                       "exist"));
  definition["modules"][0]["tasks"][0]["material"] = "Calibrated cube";
  const auto updated = admin.put("/api/curricula/" + std::to_string(curriculum_id), definition);
  ASSERT_EQ(updated.status, 200) << updated.body;
  const auto materials = admin.get("/api/materials").json()["materials"];
  ASSERT_EQ(materials.size(), 1u);
  EXPECT_EQ(materials[0]["tasks"], json::array({"palpation"}));

  // The session runs with it, its recording says so, and the replay rebuilds the same scene.
  Running run;
  ASSERT_NO_FATAL_FAILURE(start_booked_session(run));
  EXPECT_EQ(db_text("SELECT material FROM recordings WHERE id = " + std::to_string(run.recording)),
            "Calibrated cube");
  std::this_thread::sleep_for(1s);
  const auto stopped =
      as(trainee_).post("/api/sessions/" + std::to_string(run.session) + "/stop", json::object());
  ASSERT_EQ(stopped.status, 200) << stopped.body;
  cancel(run.booking);
  auto replay = view(
      "/api/recordings/" + std::to_string(run.recording) + "/replay?fps=10&width=160&height=120",
      kInstructor);
  replay->send({{"type", "speed"}, {"value", 4}});
  replay->send({{"type", "play"}});
  ASSERT_TRUE(
      replay->read_until([&] { return replay->metrics.value("state", "") == "ended"; }, 30s))
      << replay->metrics.dump() << (replay->closed ? replay->closed->close_reason : "");
  EXPECT_FALSE(replay->frames.empty());
}

TEST_F(TissueCalibration, ARunningJobCancels) {
  auto& admin = as(kAdmin);
  const auto created = admin.post("/api/calibration/jobs", {{"scene", kCube},
                                                            {"method", "ga"},
                                                            {"per", "node"},
                                                            {"budget", 20000},
                                                            {"data", example()}});
  ASSERT_EQ(created.status, 201) << created.body;
  const auto id = created.json()["job"]["id"].get<std::int64_t>();
  // Running, with progress, before the cancel.
  const auto deadline = Clock::now() + 30s;
  while (
      Clock::now() < deadline &&
      admin.get("/api/calibration/jobs/" + std::to_string(id)).json()["job"]["progress"].is_null())
    std::this_thread::sleep_for(100ms);
  const auto cancelled =
      admin.post("/api/calibration/jobs/" + std::to_string(id) + "/cancel", json::object());
  ASSERT_EQ(cancelled.status, 200) << cancelled.body;
  const json ended = wait_for_job(id, 30s);
  EXPECT_EQ(ended["job"]["status"], "cancelled") << ended.dump();
  EXPECT_EQ(ended["job"]["error"], "cancelled");
  EXPECT_LT(ended["job"]["progress"]["evaluations"].get<int>(), 20000);
  EXPECT_TRUE(is_error(
      admin.post("/api/calibration/jobs/" + std::to_string(id) + "/cancel", json::object()), 409,
      "calibration job " + std::to_string(id) + " has ended (cancelled)"));
  EXPECT_TRUE(is_error(
      admin.post("/api/materials", {{"job", id}, {"name", "Half a fit"}}), 409,
      "calibration job " + std::to_string(id) + " is cancelled: only a finished fit is saved"));
}

}  // namespace
}  // namespace incise::server::test
