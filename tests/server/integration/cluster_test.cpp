// The platform as it runs beyond one machine (docs/scale_out.md), all real: PostgreSQL (the pg/
// run's cluster), Debian's nginx as the load balancer (round robin, WebSocket upgrades) with the
// configuration deploy/run-cluster.sh uses, three incise-server nodes and the real agents. Agents
// land on different nodes; a session starts on the node holding its station's agent whichever
// node the request reaches; a trainee watches and pauses it through another node; kill -9 that
// node mid-session: the others keep serving, its session is aborted within the heartbeat timeout,
// its recording replays to its last stored chunk, and its agent reconnects to a live node. A
// station retired through one node has its agent's link closed by the node that holds it.
#include <signal.h>

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "db/database.h"
#include "db/statement.h"
#include "live_fixture.h"
#include "nginx_process.h"
#include "server/demo_data.h"
#include "tests/support/wait_for.h"

namespace incise::server::test {
namespace {

using incise::test::wait_for;

std::string node_of_station(db::Database& db, int station) {
  auto q = db.prepare("SELECT node_id FROM station_links WHERE station_id = ?");
  q.bind(1, station);
  return q.step() ? q.text(0) : "";
}

std::int64_t count(db::Database& db, const std::string& sql, std::int64_t id) {
  auto q = db.prepare(sql);
  q.bind(1, id);
  return q.step() ? q.int64(0) : 0;
}

std::unique_ptr<ChildProcess> agent(unsigned short port, const char* token) {
  return std::make_unique<ChildProcess>(
      std::vector<std::string>{INCISE_AGENT_BIN, "--server",
                               "ws://127.0.0.1:" + std::to_string(port) + "/agent", "--rate",
                               "500"},
      incise::test::environment_with("INCISE_STATION_TOKEN", token));
}

TEST(Cluster, ThreeNodesBehindNginxLoseNothingWhenOneDies) {
  if (!std::getenv("INCISE_TEST_DATABASE")) GTEST_SKIP() << "runs on PostgreSQL (pg/)";
  signal(SIGPIPE, SIG_IGN);
  const std::vector<std::string> timeout = {"--node-timeout", "3"};
  const auto with = [&](const char* id) {
    auto args = timeout;
    args.insert(args.end(), {"--node-id", id});
    return args;
  };
  ServerProcess a(with("node-a"));
  ServerProcess b(with("node-b"), &a);
  ServerProcess c(with("node-c"), &a);
  std::map<std::string, ServerProcess*> nodes = {{"node-a", &a}, {"node-b", &b}, {"node-c", &c}};
  db::Database db(a.database());
  Nginx lb({a.port(), b.port(), c.port()});

  // The three demo stations' agents connect through the balancer, one after another: round robin
  // puts them on different nodes.
  const std::vector<std::pair<int, const char*>> stations = {
      {1, kDemoStationToken}, {2, kDemoSurgicalStationToken}, {3, kDemoArthroscopyStationToken}};
  std::vector<std::unique_ptr<ChildProcess>> agents;
  std::set<std::string> agent_nodes;
  for (const auto& [station, token] : stations) {
    agents.push_back(agent(lb.port(), token));
    ASSERT_TRUE(wait_for([&] { return !node_of_station(db, station).empty(); }, 10s))
        << agents.back()->stderr_text() << lb.log();
    agent_nodes.insert(node_of_station(db, station));
  }
  EXPECT_EQ(agent_nodes.size(), 3u) << "agents on the same node";

  // The trainee logs in, books Station 1 and starts a session, all through the balancer: the
  // start is forwarded to the node holding the station's agent, which runs the session.
  HttpClient trainee("127.0.0.1", lb.port());
  ASSERT_EQ(trainee.login(kTrainee.username, kTrainee.password).status, 200);
  const auto now = std::chrono::duration_cast<std::chrono::seconds>(
                       std::chrono::system_clock::now().time_since_epoch())
                       .count();
  const auto booked =
      trainee.post("/api/bookings", {{"station_id", 1},
                                     {"starts_at", utc_text(now - now % 900)},
                                     {"ends_at", utc_text(now - now % 900 + 3600)}});
  ASSERT_EQ(booked.status, 201) << booked.body;
  for (int i = 0; i < 3; ++i) {
    // Each node reports the station online, whichever holds its agent.
    const auto stations_seen = trainee.get("/api/stations").json();
    for (const auto& s : stations_seen)
      EXPECT_TRUE(s["online"].get<bool>()) << s.dump();
    ASSERT_EQ(stations_seen.size(), stations.size());
  }
  const auto started = trainee.post("/api/sessions", {{"station_id", 1}, {"task", "palpation"}});
  ASSERT_EQ(started.status, 201) << started.body;
  const auto session = started.json()["id"].get<std::int64_t>();
  const auto recording = started.json()["live"]["recording_id"].get<std::int64_t>();
  const auto sid = std::to_string(session);
  const auto owner = node_of_station(db, 1);
  {
    auto q = db.prepare("SELECT node_id FROM sessions WHERE id = ?");
    q.bind(1, session);
    ASSERT_TRUE(q.step());
    EXPECT_EQ(q.text(0), owner) << "the session runs where its station's agent is";
  }
  std::string other;  // a node that does not run it
  for (const auto& [id, _] : nodes) {
    if (id != owner) other = id;
  }
  const auto cookie = *trainee.cookie("incise_session");

  // The trainee's browser on another node watches it, pauses and resumes it.
  Viewer far(nodes[other]->port(), "/api/sessions/" + sid + "/view?fps=10&width=160&height=120",
             cookie);
  ASSERT_TRUE(far.read_until([&] { return far.frames.size() >= 5; }, 20s))
      << nodes[other]->process().stderr_text();
  EXPECT_EQ(far.metrics.value("state", ""), "running");
  EXPECT_EQ(far.frames.front().width, 160);
  HttpClient at_other("127.0.0.1", nodes[other]->port());
  at_other.set_cookie("incise_session", cookie);
  const auto paused = at_other.post("/api/sessions/" + sid + "/pause", nlohmann::json::object());
  ASSERT_EQ(paused.status, 200) << paused.body;
  EXPECT_EQ(paused.json()["live"]["state"], "paused") << paused.body;
  EXPECT_TRUE(far.read_until([&] { return far.metrics.value("state", "") == "paused"; }, 5s));
  const auto resumed = at_other.post("/api/sessions/" + sid + "/resume", nlohmann::json::object());
  ASSERT_EQ(resumed.status, 200) << resumed.body;
  // A forwarded request is answered where it lands, never forwarded again: that node does not
  // run the session.
  const auto looped =
      at_other.request(http::verb::post, "/api/sessions/" + sid + "/pause", "{}",
                       {{"Content-Type", "application/json"}, {"X-Incise-Forwarded-By", "node-x"}});
  EXPECT_EQ(looped.status, 409) << looped.body;
  // And through the balancer, wherever it lands.
  Viewer near(lb.port(), "/api/sessions/" + sid + "/view?fps=10&width=160&height=120", cookie);
  ASSERT_TRUE(near.read_until([&] { return near.frames.size() >= 3; }, 20s)) << lb.log();

  // Some of the recording is stored (a chunk every 0.5 s); then the owner dies.
  ASSERT_TRUE(wait_for(
      [&] {
        return count(db, "SELECT COUNT(*) FROM recording_chunks WHERE recording_id = ?",
                     recording) >= 3;
      },
      20s));
  nodes[owner]->process().send_signal(SIGKILL);
  const auto killed = Clock::now();
  // The view through the other node ends with it.
  EXPECT_TRUE(far.read_until([&] { return far.closed.has_value(); }, 10s))
      << "the forwarded view outlived its node";

  // Until its heartbeat is stale, calls about its session find it gone: 503, try again.
  const auto gone = at_other.get("/api/sessions/" + sid);
  EXPECT_TRUE(is_error(gone, 503)) << gone.body;
  EXPECT_EQ(gone.retry_after, "2");
  {
    WsClient refused("127.0.0.1", nodes[other]->port(), "/api/sessions/" + sid + "/view",
                     {{"Cookie", "incise_session=" + cookie}});
    const auto event = refused.read();
    EXPECT_EQ(event.close_code, 1013) << event.close_reason << event.error;
  }

  // The others keep serving, through the balancer.
  for (int i = 0; i < 6; ++i) {
    const auto me = trainee.get("/api/me");
    EXPECT_EQ(me.status, 200) << me.body << lb.log();
  }
  // Its session is aborted within the heartbeat timeout (3 s) and a sweep (every 0.5 s).
  std::string state;
  ASSERT_TRUE(wait_for(
      [&] {
        const auto got = at_other.get("/api/sessions/" + sid);
        state = got.status == 200 ? got.json().value("state", "") : "";
        return state == "aborted";
      },
      15s))
      << state;
  const auto aborted_after = std::chrono::duration<double>(Clock::now() - killed).count();
  EXPECT_LT(aborted_after, 3 + 0.5 + 2.0) << "timeout, sweep interval, and slack";
  std::cerr << "aborted " << aborted_after << " s after kill -9\n";

  // Its recording replays, on any node, to its last stored chunk.
  const auto last_t0_us =
      count(db, "SELECT MAX(t0_us) FROM recording_chunks WHERE recording_id = ?", recording);
  HttpClient instructor("127.0.0.1", lb.port());
  ASSERT_EQ(instructor.login(kInstructor.username, kInstructor.password).status, 200);
  Viewer replay(
      lb.port(),
      "/api/recordings/" + std::to_string(recording) + "/replay?fps=5&width=160&height=120",
      *instructor.cookie("incise_session"));
  replay.send({{"type", "speed"}, {"value", 4}});
  replay.send({{"type", "play"}});
  ASSERT_TRUE(replay.read_until([&] { return replay.metrics.value("state", "") == "ended"; }, 60s))
      << replay.metrics.dump()
      << (replay.closed ? replay.closed->close_reason + replay.closed->error : "");
  EXPECT_GE(replay.metrics["duration_s"].get<double>(), last_t0_us * 1e-6);
  EXPECT_FALSE(replay.frames.empty());

  // Its station's agent reconnects, through the balancer, to a live node; a new session starts
  // there.
  std::string relinked;
  ASSERT_TRUE(wait_for(
      [&] {
        relinked = node_of_station(db, 1);
        return !relinked.empty() && relinked != owner;
      },
      20s))
      << agents[0]->stderr_text();
  const auto again = trainee.post("/api/sessions", {{"station_id", 1}, {"task", "palpation"}});
  ASSERT_EQ(again.status, 201) << again.body;
  const auto again_id = again.json()["id"].get<std::int64_t>();
  {
    auto q = db.prepare("SELECT node_id FROM sessions WHERE id = ?");
    q.bind(1, again_id);
    ASSERT_TRUE(q.step());
    EXPECT_EQ(q.text(0), relinked);
  }
  EXPECT_EQ(
      trainee.post("/api/sessions/" + std::to_string(again_id) + "/stop", nlohmann::json::object())
          .status,
      200);

  // An admin retires the Arthroscopy station on a node that does not hold its agent: the change
  // goes to the node that does, which closes the agent's link at once.
  const auto knee_node = node_of_station(db, 3);
  ServerProcess* elsewhere = nullptr;
  for (const auto& [id, node] : nodes) {
    if (id != knee_node && id != owner) elsewhere = node;
  }
  ASSERT_NE(elsewhere, nullptr);
  HttpClient admin("127.0.0.1", elsewhere->port());
  ASSERT_EQ(admin.login(kAdmin.username, kAdmin.password).status, 200);
  const auto retired =
      admin.request(http::verb::patch, "/api/stations/3", R"({"retired": true})",
                    {{"Content-Type", "application/json"}, {"Origin", admin.origin()}});
  ASSERT_EQ(retired.status, 200) << retired.body;
  EXPECT_TRUE(wait_for([&] { return node_of_station(db, 3).empty(); }, 10s))
      << "the retired station's agent is still linked to " << node_of_station(db, 3);
}

}  // namespace
}  // namespace incise::server::test
