// bench_cluster: what three local nodes hold (docs/scale_out.md). Three incise-server nodes on one
// PostgreSQL behind nginx, on this machine; the three demo stations' agents connect through the
// balancer (one per node), an instructor starts each station's task through the balancer, and
// each session is watched by two viewers at 320x240, 15 fps: one on the node that runs it, one on
// another node (forwarded). Per session: the node, the achieved tick rate (median of the 1 s
// samples in the metrics) and the frames per second each viewer received.
// Usage: INCISE_TEST_DATABASE=postgresql://... bench_cluster [--seconds N]   (default 30;
// deploy/bench.sh starts a throwaway cluster for it). Prints one line per session.
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <thread>
#include <vector>

#include "bench/median.h"
#include "db/database.h"
#include "db/statement.h"
#include "server/demo_data.h"
#include "tests/server/integration/nginx_process.h"
#include "tests/support/ws_client.h"

using namespace incise::server::test;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

using incise::bench::median;

struct Watch {
  long frames = 0;
  double seconds = 0;              // how long it watched: the run, or until the session ended
  std::vector<double> tick_rates;  // sim_rate_hz, sampled once a second
  std::string error;
};

// Watches `target` on `port` until `end`, acknowledging frames like the dashboard.
void watch(unsigned short port, const std::string& target, const std::string& cookie,
           Clock::time_point end, Watch& out) {
  const auto start = Clock::now();
  const auto stop = [&] {
    out.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  };
  try {
    WsClient ws("127.0.0.1", port, target, {{"Cookie", "incise_session=" + cookie}});
    auto next_sample = Clock::now() + 1s;
    while (Clock::now() < end) {
      const auto event = ws.read();
      if (event.closed) {
        out.error = event.close_reason.empty() ? event.error : event.close_reason;
        return stop();
      }
      if (!event.text) {
        std::uint32_t number = 0;
        std::memcpy(&number, event.message.data(), 4);
        ws.send_text(nlohmann::json{{"type", "ack"}, {"frame", number}}.dump());
        ++out.frames;
      } else if (Clock::now() >= next_sample) {
        const auto m = nlohmann::json::parse(event.message);
        if (m.value("sim_rate_hz", 0.0) > 0) out.tick_rates.push_back(m["sim_rate_hz"]);
        next_sample += 1s;
      }
    }
  } catch (const std::exception& e) {
    out.error = e.what();
  }
  stop();
}

std::string node_of(incise::db::Database& db, const char* sql, std::int64_t id) {
  auto q = db.prepare(sql);
  q.bind(1, id);
  return q.step() ? q.text(0) : "";
}

}  // namespace

int main(int argc, char** argv) {
  signal(SIGPIPE, SIG_IGN);
  int seconds = 30;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == "--seconds") seconds = std::max(1, std::atoi(argv[i + 1]));
  }
  if (!std::getenv("INCISE_TEST_DATABASE")) {
    std::cerr << "bench_cluster: set INCISE_TEST_DATABASE to a PostgreSQL server's URL\n";
    return 2;
  }
  ServerProcess a({"--node-id", "node-a"});
  ServerProcess b({"--node-id", "node-b"}, &a);
  ServerProcess c({"--node-id", "node-c"}, &a);
  const std::map<std::string, unsigned short> ports = {
      {"node-a", a.port()}, {"node-b", b.port()}, {"node-c", c.port()}};
  incise::db::Database db(a.database());
  Nginx lb({a.port(), b.port(), c.port()});

  struct Station {
    int id;
    const char* token;
    const char* task;
    std::vector<std::string> devices;
  };
  const std::string agents_dir = std::string(INCISE_SOURCE_DIR) + "/deploy/agent/";
  const std::vector<Station> stations = {
      {1, incise::server::kDemoStationToken, "palpation", {}},
      {2,
       incise::server::kDemoSurgicalStationToken,
       "liver_cut",
       {"--script", agents_dir + "liver_cut_demo.json"}},
      {3,
       incise::server::kDemoArthroscopyStationToken,
       "knee_tour",
       {"--device", "knee-scope:" + agents_dir + "knee_scope_tour.json", "--device",
        "knee-instrument:" + agents_dir + "knee_probe_tour.json"}}};
  std::vector<std::unique_ptr<ChildProcess>> agents;
  for (const auto& s : stations) {
    std::vector<std::string> args = {INCISE_AGENT_BIN, "--server",
                                     "ws://127.0.0.1:" + std::to_string(lb.port()) + "/agent"};
    args.insert(args.end(), s.devices.begin(), s.devices.end());
    agents.push_back(std::make_unique<ChildProcess>(
        args, incise::test::environment_with("INCISE_STATION_TOKEN", s.token)));
    const auto deadline = Clock::now() + 10s;
    while (Clock::now() < deadline &&
           node_of(db, "SELECT node_id FROM station_links WHERE station_id = ?", s.id).empty())
      std::this_thread::sleep_for(20ms);
  }

  HttpClient instructor("127.0.0.1", lb.port());
  instructor.login(kInstructor.username, kInstructor.password);
  const auto cookie = *instructor.cookie("incise_session");
  struct Running {
    std::string task, node;
    std::int64_t id = 0;
    Watch direct, forwarded;
  };
  std::vector<Running> sessions(stations.size());
  for (std::size_t i = 0; i < stations.size(); ++i) {
    const auto started = instructor.post(
        "/api/sessions", {{"station_id", stations[i].id}, {"task", stations[i].task}});
    if (started.status != 201) {
      std::cerr << "bench_cluster: cannot start " << stations[i].task << ": " << started.body
                << "\n";
      return 1;
    }
    sessions[i].task = stations[i].task;
    sessions[i].id = started.json()["id"].get<std::int64_t>();
    sessions[i].node = node_of(db, "SELECT node_id FROM sessions WHERE id = ?", sessions[i].id);
  }

  const auto end = Clock::now() + std::chrono::seconds(seconds);
  std::vector<std::thread> viewers;
  for (auto& s : sessions) {
    const auto target =
        "/api/sessions/" + std::to_string(s.id) + "/view?fps=15&width=320&height=240";
    const auto owner = ports.at(s.node);
    unsigned short other = 0;
    for (const auto& [node, port] : ports) {
      if (node != s.node) other = port;
    }
    viewers.emplace_back(watch, owner, target, cookie, end, std::ref(s.direct));
    viewers.emplace_back(watch, other, target, cookie, end, std::ref(s.forwarded));
  }
  for (auto& t : viewers)
    t.join();
  for (const auto& s : sessions)
    instructor.post("/api/sessions/" + std::to_string(s.id) + "/stop", nlohmann::json::object());

  std::printf(
      "bench_cluster: 3 nodes (PostgreSQL, nginx), %zu sessions, %zu viewers at 320x240 "
      "15 fps requested, %d s, %u cores\n",
      sessions.size(), 2 * sessions.size(), seconds, std::thread::hardware_concurrency());
  const auto per_second = [](const Watch& w) { return w.seconds > 0 ? w.frames / w.seconds : 0.0; };
  for (const auto& s : sessions) {
    auto rates = s.direct.tick_rates;
    rates.insert(rates.end(), s.forwarded.tick_rates.begin(), s.forwarded.tick_rates.end());
    std::printf(
        "session %-10s on %s: tick rate median %.0f Hz (target 500); frames %.1f/s "
        "direct, %.1f/s forwarded",
        s.task.c_str(), s.node.c_str(), median(rates), per_second(s.direct),
        per_second(s.forwarded));
    if (!s.direct.error.empty()) {
      // A task may end itself (its completion criteria met): the rates are over its time.
      std::printf(" (watched %.0f s: %s)", s.direct.seconds, s.direct.error.c_str());
    }
    std::printf("\n");
  }
  return 0;
}
