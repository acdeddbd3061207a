// A live session that falls behind real time says so and sheds work, and recovers when the load
// goes: server/live/live_session.h with its real thread, SQLite file and renderer, throttled
// through LiveSessionParams::after_tick (pace_monitor_test.cpp has the rules on scripted clocks).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <thread>

#include "db/database.h"
#include "db/migrations.h"
#include "db/recordings_repo.h"
#include "db/training_repo.h"
#include "db/users_repo.h"
#include "server/live/live_session.h"
#include "sim/io/scene_json.h"
#include "tests/server/live/test_scene.h"
#include "tests/support/temp_dir.h"

namespace incise::server::live {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
constexpr std::int64_t kNow = 1'800'000'000;

// Polls status() until `done` holds for it or `timeout` passes; returns the last status.
template <class Done>
nlohmann::json status_when(const LiveSession& session, Done done, std::chrono::seconds timeout) {
  const auto deadline = Clock::now() + timeout;
  nlohmann::json status = session.status();
  while (!done(status) && Clock::now() < deadline) {
    std::this_thread::sleep_for(20ms);
    status = session.status();
  }
  return status;
}

TEST(LiveSessionPace, AThrottledSessionReportsBehindRealTimeShedsAndRecovers) {
  incise::test::TempDir dir;
  const auto db_path = dir.path() / "incise.db";
  LiveSessionParams params;
  {
    db::Database db(db_path);
    db::apply_migrations(db);
    const auto trainee =
        db::UsersRepo(db).create({"tess", "Tess", db::Role::trainee, "a long password"}, kNow).id;
    params.session_id = db::TrainingRepo(db).create_session(trainee, std::nullopt, "p", kNow);
    params.recording_id = db::RecordingsRepo(db).create(params.session_id, "scenes/palpation.json",
                                                        "0123456789abcdef", 0, 500, kNow);
  }
  params.database = db::DatabaseUrl::sqlite(db_path);
  // The palpation block on 2 x 2 x 1 cells: a tick costs microseconds, so that unthrottled the
  // session keeps up even on a machine busy with other tests.
  auto scene = nlohmann::json::parse(test::palpation_text());
  scene["mesh"]["box"]["cells"] = {2, 2, 1};
  params.scene = sim::parse_scene_text(scene.dump());
  // Throttled: each 2 ms tick takes 6 ms more, a third of real time.
  std::atomic<bool> throttled{false};
  params.after_tick = [&throttled] {
    if (throttled.load()) std::this_thread::sleep_for(6ms);
  };
  LiveSession session(std::move(params), {});
  session.start();
  devices::DeviceState idle;
  idle.position = {0, 0, 0.05f};
  session.on_device_state(idle, 0);

  auto keeping_up = [](const nlohmann::json& s) {
    return s["behind_real_time"] == false && s["real_time_factor"].get<double>() > 0.9;
  };
  nlohmann::json status = status_when(session, keeping_up, 10s);
  ASSERT_TRUE(keeping_up(status)) << status.dump();
  EXPECT_EQ(status["shed"], "");

  throttled = true;
  status = status_when(
      session, [](const nlohmann::json& s) { return s["shed"] == "render rate quartered"; }, 10s);
  EXPECT_EQ(status["state"], "running");
  EXPECT_EQ(status["behind_real_time"], true) << status.dump();
  EXPECT_LT(status["real_time_factor"].get<double>(), 0.5) << status.dump();
  EXPECT_EQ(status["shed"], "render rate quartered") << status.dump();
  const double simulated = session.sim_time_s();

  throttled = false;
  status = status_when(
      session, [&](const nlohmann::json& s) { return keeping_up(s) && s["shed"] == ""; }, 15s);
  EXPECT_EQ(status["behind_real_time"], false) << status.dump();
  EXPECT_GT(status["real_time_factor"].get<double>(), 0.9) << status.dump();
  EXPECT_EQ(status["shed"], "") << status.dump();
  EXPECT_GT(session.sim_time_s(), simulated);  // it went on simulating throughout

  session.stop("test over");
  EXPECT_EQ(session.state(), LiveState::finished);
}

TEST(LiveSessionPace, APausedSessionIsNotBehind) {
  LiveSessionParams params;
  params.scene = test::palpation_scene();
  params.database = db::DatabaseUrl::sqlite("/nonexistent/never-opened.db");
  LiveSession session(std::move(params), {});  // never started
  ASSERT_EQ(session.pause("coffee"), "");
  const auto status = session.status();
  EXPECT_EQ(status["behind_real_time"], false);
  EXPECT_EQ(status["lag_ms"], 0);
}

nlohmann::json link_report(const char* fault, double age_ms) {
  return {{"loop_hz", 1000},
          {"devices",
           {{{"index", 0}, {"model_age_ms", 2.0}, {"fault", "none"}},
            {{"index", 1}, {"model_age_ms", age_ms}, {"fault", fault}}}}};
}

TEST(StaleModel, OnlyTheAgentsStaleModelFaultIsAReasonToPause) {
  EXPECT_EQ(stale_model_reason(link_report("none", 12)), "");
  EXPECT_EQ(stale_model_reason(link_report("no model", 40)), "");  // the agent fades; no pause
  EXPECT_EQ(stale_model_reason(link_report("stale model", 412.4)),
            "the station's force model went stale (tool 2: 412 ms old, over the agent's safety "
            "limit); resume when the link is steady");
  // Whatever shape a report has, it is never a reason by accident.
  for (const auto& odd : {nlohmann::json(), nlohmann::json::array(), nlohmann::json{{"devices", 3}},
                          nlohmann::json{{"devices", {1, "x", nullptr}}}})
    EXPECT_EQ(stale_model_reason(odd), "") << odd;
}

TEST(StaleModel, ARunningSessionPausesOnAStaleModelAfterItsGrace) {
  LiveSessionParams params;
  params.scene = test::palpation_scene();
  params.database = db::DatabaseUrl::sqlite("/nonexistent/never-opened.db");
  params.stale_model_grace = 0ms;
  LiveSession session(std::move(params), {});  // never started: its state is all this needs
  session.set_link_report(link_report("none", 3));
  EXPECT_EQ(session.state(), LiveState::running);
  session.set_link_report(link_report("stale model", 350));
  EXPECT_EQ(session.state(), LiveState::paused);
  EXPECT_NE(session.status()["reason"].get<std::string>().find("force model went stale"),
            std::string::npos);
  EXPECT_EQ(session.status()["link"]["devices"][1]["fault"], "stale model");
}

TEST(StaleModel, AReportWithinTheGraceDoesNotPause) {
  LiveSessionParams params;
  params.scene = test::palpation_scene();
  params.database = db::DatabaseUrl::sqlite("/nonexistent/never-opened.db");
  params.stale_model_grace = std::chrono::hours(1);
  LiveSession session(std::move(params), {});
  session.set_link_report(link_report("stale model", 350));
  EXPECT_EQ(session.state(), LiveState::running);
}

}  // namespace
}  // namespace incise::server::live
