// Routing between station agents and live sessions: server/live_sessions.h, with sessions that are
// built (engine, first snapshot) but never started, so no thread, database or GPU is involved.
#include "server/live_sessions.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <limits>
#include <memory>
#include <thread>
#include <vector>

#include "tests/server/live/test_scene.h"

namespace incise::server {
namespace {

using namespace std::chrono_literals;

std::shared_ptr<live::LiveSession> unstarted_session(std::int64_t session_id,
                                                     std::int64_t station_id) {
  live::LiveSessionParams params;
  params.session_id = session_id;
  params.station_id = station_id;
  params.recording_id = 100 + session_id;
  params.scene = live::test::palpation_scene();
  params.database =
      db::DatabaseUrl::sqlite("/nonexistent/never-opened.db");  // only the session thread opens it
  return std::make_shared<live::LiveSession>(std::move(params), live::LiveSession::AgentLink{});
}

// Runs f on another thread and says whether it returned within `limit`. A hung f is left behind
// (detached): the test fails instead of hanging.
template <class F>
bool returns_within(std::chrono::milliseconds limit, F f) {
  auto done = std::make_shared<std::promise<void>>();
  auto future = done->get_future();
  std::thread([done, f = std::move(f)]() mutable {
    f();
    done->set_value();
  }).detach();
  return future.wait_for(limit) == std::future_status::ready;
}

TEST(LiveSession, BuiltButNotStarted) {
  const auto session = unstarted_session(1, 11);
  EXPECT_EQ(session->session_id(), 1);
  EXPECT_EQ(session->station_id(), 11);
  EXPECT_EQ(session->recording_id(), 101);
  EXPECT_EQ(session->state(), live::LiveState::running);
  EXPECT_EQ(session->sim_time_s(), 0.0);
  const auto status = session->status();
  EXPECT_EQ(status["state"], "running");
  EXPECT_EQ(status["agent_online"], true);
  EXPECT_EQ(status["force_models_sent"], 0);
  EXPECT_FALSE(status.contains("render_error"));  // no renderer before start()

  // The first snapshot shows the scene at rest and the tool parked above it.
  const auto snapshot = session->snapshot();
  ASSERT_NE(snapshot, nullptr);
  EXPECT_EQ(snapshot->tick, 0);
  ASSERT_NE(snapshot->surface, nullptr);
  EXPECT_EQ(snapshot->positions.rows(), 13 * 13 * 5);
  EXPECT_EQ(snapshot->tool_tip, sim::Vec3(0, 0, live::kParkedToolHeight));
  EXPECT_EQ(snapshot->tool_radius, 0.005);
  EXPECT_FALSE(snapshot->contact);
}

TEST(LiveSession, BadTickRateThrows) {
  // 0.01 Hz: a tick of 100 s would need 400,000 steps of the block's 2.5e-4 s.
  for (const double hz : {0.0, -500.0, 0.01, std::numeric_limits<double>::quiet_NaN()}) {
    live::LiveSessionParams params;
    params.scene = live::test::palpation_scene();
    params.tick_hz = hz;
    EXPECT_THROW(live::LiveSession(std::move(params), live::LiveSession::AgentLink{}),
                 std::invalid_argument)
        << hz;
  }
  live::LiveSessionParams params;  // no scene
  EXPECT_THROW(live::LiveSession(std::move(params), live::LiveSession::AgentLink{}),
               std::invalid_argument);
}

TEST(LiveSession, PauseAndResumeRules) {
  const auto session = unstarted_session(1, 11);
  EXPECT_EQ(session->resume(), "session is already running");
  EXPECT_EQ(session->pause("coffee"), "");
  EXPECT_EQ(session->state(), live::LiveState::paused);
  EXPECT_EQ(session->reason(), "coffee");
  EXPECT_EQ(session->pause("again"), "session is already paused");
  EXPECT_EQ(session->reason(), "coffee");
  EXPECT_EQ(session->resume(), "");
  EXPECT_EQ(session->state(), live::LiveState::running);
  EXPECT_EQ(session->reason(), "");

  // An agent dropping out pauses; the session cannot resume until it is back.
  session->set_agent_online(false);
  EXPECT_EQ(session->state(), live::LiveState::paused);
  EXPECT_EQ(session->reason(), "station agent offline");
  EXPECT_EQ(session->status()["agent_online"], false);
  EXPECT_EQ(session->resume(), "station agent is offline");
  EXPECT_EQ(session->state(), live::LiveState::paused);
  session->set_agent_online(true);
  EXPECT_EQ(session->state(), live::LiveState::paused);  // coming back does not resume by itself
  EXPECT_EQ(session->resume(), "");
  EXPECT_EQ(session->state(), live::LiveState::running);
}

TEST(LiveSession, DestroyingANeverStartedSessionReturns) {
  auto session = unstarted_session(1, 11);
  EXPECT_TRUE(returns_within(5s, [s = std::move(session)]() mutable { s.reset(); }));
  auto stopped = unstarted_session(2, 11);
  EXPECT_TRUE(returns_within(5s, [s = std::move(stopped)]() mutable {
    s->stop("test");
    s->stop("twice");  // idempotent
    s.reset();
  }));
}

TEST(LiveSessions, FindsSessionsByIdAndStation) {
  LiveSessions sessions;
  const auto a = unstarted_session(1, 11);
  const auto b = unstarted_session(2, 12);
  sessions.add(a);
  sessions.add(b);
  EXPECT_EQ(sessions.find(1), a);
  EXPECT_EQ(sessions.find(2), b);
  EXPECT_EQ(sessions.find(3), nullptr);
  EXPECT_EQ(sessions.active_at(11), a);
  EXPECT_EQ(sessions.active_at(12), b);
  EXPECT_EQ(sessions.active_at(13), nullptr);
  EXPECT_EQ(sessions.active_at(1), nullptr);  // a session id is not a station id

  sessions.remove(1);
  EXPECT_EQ(sessions.find(1), nullptr);
  EXPECT_EQ(sessions.active_at(11), nullptr);
  EXPECT_EQ(sessions.find(2), b);
  sessions.remove(1);  // removing twice is harmless
  sessions.remove(99);
  EXPECT_EQ(sessions.find(2), b);
}

TEST(LiveSessions, RemoveReleasesTheSession) {
  LiveSessions sessions;
  auto session = unstarted_session(1, 11);
  const std::weak_ptr<live::LiveSession> watch = session;
  sessions.add(session);
  session.reset();
  EXPECT_FALSE(watch.expired());  // the registry holds it
  EXPECT_TRUE(returns_within(5s, [&] { sessions.remove(1); }));
  EXPECT_TRUE(watch.expired());
}

TEST(LiveSessions, AgentEventsReachOnlyTheirStationsSession) {
  LiveSessions sessions;
  const auto a = unstarted_session(1, 11);
  const auto b = unstarted_session(2, 12);
  sessions.add(a);
  sessions.add(b);

  sessions.on_agent(11, false);
  EXPECT_EQ(a->state(), live::LiveState::paused);
  EXPECT_EQ(a->reason(), "station agent offline");
  EXPECT_FALSE(a->agent_online());
  EXPECT_EQ(b->state(), live::LiveState::running);
  EXPECT_TRUE(b->agent_online());

  sessions.on_agent(13, false);  // a station without a session: nothing happens
  EXPECT_EQ(b->state(), live::LiveState::running);

  sessions.on_agent(11, true);
  EXPECT_TRUE(a->agent_online());
  EXPECT_EQ(a->resume(), "");
}

TEST(LiveSessions, StopAllForgetsEverySession) {
  LiveSessions sessions;
  sessions.add(unstarted_session(1, 11));
  sessions.add(unstarted_session(2, 12));
  EXPECT_TRUE(returns_within(5s, [&] { sessions.stop_all("server shutting down"); }));
  EXPECT_EQ(sessions.find(1), nullptr);
  EXPECT_EQ(sessions.find(2), nullptr);
  EXPECT_EQ(sessions.active_at(11), nullptr);
}

// Two starts racing for a station (requests now run side by side): only one holds the claim, until
// its session is registered or it gives up; a station with an active session cannot be claimed.
TEST(LiveSessions, OneStartAtATimeClaimsAStation) {
  LiveSessions sessions;
  EXPECT_TRUE(sessions.claim(11));
  EXPECT_TRUE(sessions.starting(11));
  EXPECT_FALSE(sessions.claim(11)) << "a second start while the first holds the station";
  EXPECT_TRUE(sessions.claim(12)) << "another station is free";
  sessions.release_claim(12);
  EXPECT_FALSE(sessions.starting(12));
  EXPECT_TRUE(sessions.claim(12)) << "a start that gave up frees the station";

  sessions.add(unstarted_session(1, 11));
  EXPECT_FALSE(sessions.starting(11)) << "registering the session ends the claim";
  EXPECT_FALSE(sessions.claim(11)) << "the station's session is active";
  sessions.remove(1);
  EXPECT_TRUE(sessions.claim(11));

  // Many threads at once: exactly one wins.
  LiveSessions raced;
  std::atomic<int> won = 0;
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&] { won += raced.claim(21) ? 1 : 0; });
  for (auto& t : threads)
    t.join();
  EXPECT_EQ(won, 1);
}

}  // namespace
}  // namespace incise::server
