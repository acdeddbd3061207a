// bench_live: the live path's latencies on loopback, with the real server and the real agent.
//   device state -> force model round trip (the agent measures it from the echoed timestamp)
//   sim snapshot -> frame handed to the viewer's socket (the server measures it per frame)
//   achieved simulation tick rate, frames received by one 640x480 viewer at 30 fps
// Usage: bench_live [--seconds N]   (default 30). Prints one line per figure.
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "bench/median.h"
#include "tests/server/integration/server_fixture.h"
#include "tests/support/ws_client.h"

using namespace incise::server::test;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

using incise::bench::median;

}  // namespace

int main(int argc, char** argv) {
  signal(SIGPIPE, SIG_IGN);
  int seconds = 30;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == "--seconds") seconds = std::max(1, std::atoi(argv[i + 1]));
  }
  ServerProcess server;
  ChildProcess agent(
      {INCISE_AGENT_BIN, "--server", "ws://127.0.0.1:" + std::to_string(server.port()) + "/agent",
       "--rate", "500"},
      incise::test::environment_with("INCISE_STATION_TOKEN", kStationToken));
  auto client = server.client();
  client->login(kInstructor.username, kInstructor.password);
  HttpResponse started;
  for (int attempt = 0; attempt < 100; ++attempt) {
    started = client->post("/api/sessions", {{"station_id", 1}, {"task", "palpation"}});
    if (started.status == 201) break;
    std::this_thread::sleep_for(50ms);  // until the agent is online
  }
  if (started.status != 201) {
    std::cerr << "bench_live: cannot start a session: " << started.body << "\n";
    return 1;
  }
  const auto session = std::to_string(started.json()["id"].get<long long>());
  WsClient viewer("127.0.0.1", server.port(),
                  "/api/sessions/" + session + "/view?fps=30&width=640&height=480",
                  {{"Cookie", "incise_session=" + *client->cookie("incise_session")}});
  std::vector<double> latencies, rates;
  long frames = 0;
  std::size_t bytes = 0;
  const auto end = Clock::now() + std::chrono::seconds(seconds);
  auto next_sample = Clock::now() + 1s;
  while (Clock::now() < end) {
    const auto event = viewer.read();
    if (event.closed) break;
    if (!event.text) {
      std::uint32_t number = 0;
      std::memcpy(&number, event.message.data(), 4);
      viewer.send_text(nlohmann::json{{"type", "ack"}, {"frame", number}}.dump());
      ++frames;
      bytes += event.message.size();
    } else if (Clock::now() >= next_sample) {
      // Each metrics message carries the median of the last frames' latencies; sample once a
      // second so that the windows barely overlap.
      const auto m = nlohmann::json::parse(event.message);
      if (m.value("frame_latency_ms", -1.0) >= 0) latencies.push_back(m["frame_latency_ms"]);
      if (m.value("sim_rate_hz", 0.0) > 0) rates.push_back(m["sim_rate_hz"]);
      next_sample += 1s;
    }
  }
  client->post("/api/sessions/" + session + "/stop", nlohmann::json::object());
  agent.send_signal(SIGINT);
  agent.wait_for_exit(5s);

  std::printf("bench_live: %d s, one viewer at 640x480, 30 fps requested\n", seconds);
  std::printf("frames received: %.1f per s, %.1f KiB median size\n",
              static_cast<double>(frames) / seconds,
              frames ? static_cast<double>(bytes) / frames / 1024 : 0.0);
  std::printf("snapshot -> frame sent latency: median %.2f ms\n", median(latencies));
  std::printf("simulation tick rate: median %.1f Hz (target 500)\n", median(rates));
  // The agent's own statistics line (round trip, loop jitter), as it printed it at exit.
  const auto log = agent.stderr_text() + agent.stdout_text();
  std::size_t at = 0;
  while ((at = log.find('\n', at)) != std::string::npos) {
    const auto start = log.rfind('\n', at - 1);
    const auto line = log.substr(start == std::string::npos ? 0 : start + 1,
                                 at - (start == std::string::npos ? 0 : start + 1));
    if (line.find("round trip") != std::string::npos) std::printf("agent: %s\n", line.c_str());
    ++at;
  }
  return 0;
}
