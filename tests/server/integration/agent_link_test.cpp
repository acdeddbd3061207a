// The station-agent WebSocket of the real server, with the real incise-agent and with
// misbehaving agents played by the test.
#include <signal.h>

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "server_fixture.h"
#include "tests/support/ws_client.h"

namespace incise::server::test {
namespace {

using namespace std::chrono_literals;

class AgentLink : public ServerTest {
 protected:
  std::unique_ptr<ChildProcess> start_agent() {
    return std::make_unique<ChildProcess>(
        std::vector<std::string>{INCISE_AGENT_BIN, "--server",
                                 "ws://127.0.0.1:" + std::to_string(server().port()) + "/agent",
                                 "--rate", "250"},
        incise::test::environment_with("INCISE_STATION_TOKEN", kStationToken));
  }

  // Whether Station 1 reaches `online` within `timeout`, polling /api/stations.
  bool station_1_becomes(bool online, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    do {
      if (station_1_online() == online) return true;
      std::this_thread::sleep_for(25ms);
    } while (std::chrono::steady_clock::now() < deadline);
    return false;
  }

  bool station_1_online() {
    for (const auto& s : as(kTrainee).get("/api/stations").json()) {
      if (s["name"] == "Station 1") return s["online"].get<bool>();
    }
    return false;
  }

  std::unique_ptr<WsClient> connect() {
    return std::make_unique<WsClient>("127.0.0.1", server().port());
  }

  static std::string hello(const std::string& token, int protocol = 1) {
    return nlohmann::json{{"type", "hello"},
                          {"protocol", protocol},
                          {"station_token", token},
                          {"agent", "server_integration_tests"}}
        .dump();
  }
};

TEST_F(AgentLink, TheRealAgentBringsTheStationOnlineUntilItStops) {
  ASSERT_FALSE(station_1_online());
  auto agent = start_agent();
  EXPECT_TRUE(station_1_becomes(true, 3s)) << agent->stderr_text();
  std::this_thread::sleep_for(300ms);  // device states flow meanwhile
  EXPECT_TRUE(station_1_online());
  agent->send_signal(SIGTERM);
  EXPECT_EQ(agent->wait_for_exit(3s), 0) << agent->stderr_text();
  EXPECT_TRUE(station_1_becomes(false, 3s));
}

TEST_F(AgentLink, MisbehavingAgentsAreClosedAndTheRealOneStays) {
  auto agent = start_agent();
  ASSERT_TRUE(station_1_becomes(true, 3s)) << agent->stderr_text();
  const auto bench = as(kAdmin).post("/api/stations", {{"name", "Test bench"}});
  ASSERT_EQ(bench.status, 201) << bench.body;
  const auto bench_token = bench.json()["token"].get<std::string>();

  {
    auto ws = connect();
    ws->send_text(hello("not-a-station-token"));
    const auto event = ws->read();
    EXPECT_TRUE(event.closed) << event.message;
    EXPECT_EQ(event.close_code, 1008) << event.error;
    EXPECT_EQ(event.close_reason, "unknown station token");
  }
  {
    auto ws = connect();
    ws->send_text(hello(kStationToken, 2));
    const auto event = ws->read();
    EXPECT_EQ(event.close_code, 1008) << event.error;
    EXPECT_EQ(event.close_reason, "protocol 2 not supported (server speaks 1)");
  }
  {
    auto ws = connect();
    ws->send_binary({1, 0, 0, 0});
    const auto event = ws->read();
    EXPECT_EQ(event.close_code, 1008) << event.error;
    EXPECT_EQ(event.close_reason, "the first message must be the hello");
  }
  {
    // A second link with the real agent's token is refused while the real one holds the station,
    // and retrying is invited (1013): a stolen token takes nothing over.
    auto ws = connect();
    ws->send_text(hello(kStationToken));
    const auto event = ws->read();
    EXPECT_TRUE(event.closed);
    EXPECT_EQ(event.close_code, 1013) << event.error;
    EXPECT_EQ(event.close_reason,
              "station Station 1 already has a connected agent (from 127.0.0.1); try again once "
              "it has gone");
  }
  {
    // A valid hello of another station, then a frame shorter than a header.
    auto ws = connect();
    ws->send_text(hello(bench_token));
    const auto welcome = ws->read();
    ASSERT_FALSE(welcome.closed) << welcome.close_code << " " << welcome.close_reason;
    const auto w = nlohmann::json::parse(welcome.message, nullptr, false);
    EXPECT_EQ(w["type"], "welcome") << welcome.message;
    EXPECT_EQ(w["protocol"], 1);
    EXPECT_EQ(w["station_name"], "Test bench");
    ws->send_binary({1, 0, 0, 0, 0});
    const auto event = ws->read();
    EXPECT_TRUE(event.closed);
    EXPECT_EQ(event.close_code, 1007) << event.error;
    EXPECT_FALSE(event.close_reason.empty());
  }
  {
    auto ws = connect();
    ws->send_text(hello(bench_token));
    ASSERT_FALSE(ws->read().closed);
    ws->send_binary(std::vector<std::uint8_t>(5000, 0));
    const auto event = ws->read();
    EXPECT_EQ(event.close_code, 1009) << event.error;
    EXPECT_EQ(event.close_reason, "message of 5000 bytes exceeds 4096");
  }
  {
    auto ws = connect();
    ws->send_text(hello(bench_token));
    ASSERT_FALSE(ws->read().closed);
    ws->send_text(R"({"type": "chat"})");
    const auto event = ws->read();
    EXPECT_EQ(event.close_code, 1008) << event.error;
    EXPECT_EQ(event.close_reason,
              "text message of type \"chat\" is not part of protocol 1 (expected link)");
  }
  {
    // A link report with a bad field: closed with 1007 and the field.
    auto ws = connect();
    ws->send_text(hello(bench_token));
    ASSERT_FALSE(ws->read().closed);
    ws->send_text(R"({"type": "link", "loop_hz": 1000, "rtt_p50_ms": 1, "rtt_p99_ms": 2,
                      "loss_down": 2, "states_sent": 1, "states_held": 0, "devices": []})");
    const auto event = ws->read();
    EXPECT_EQ(event.close_code, 1007) << event.error;
    EXPECT_EQ(event.close_reason, "link: \"loss_down\" must be in [0, 1], got 2");
  }

  // The real agent never noticed: still connected, on its first connection.
  EXPECT_TRUE(station_1_online());
  EXPECT_TRUE(agent->running());
  const auto log = agent->stderr_text();
  std::size_t connections = 0;
  for (auto at = log.find("connected to "); at != std::string::npos;
       at = log.find("connected to ", at + 1)) {
    ++connections;
  }
  EXPECT_EQ(connections, 1u) << log;
  EXPECT_EQ(log.find("link lost"), std::string::npos) << log;
}

TEST_F(AgentLink, AConnectionThatNeverSaysHelloIsClosed) {
  auto ws = connect();
  const auto start = std::chrono::steady_clock::now();
  const auto event = ws->read();  // the client answers the server's keep-alive pings meanwhile
  EXPECT_TRUE(event.closed);
  EXPECT_EQ(event.close_code, 1008) << event.error;
  EXPECT_EQ(event.close_reason, "no hello within 5 s");
  EXPECT_GE(std::chrono::steady_clock::now() - start, 4s);
}

TEST_F(AgentLink, OtherWebSocketPathsAreRefused) {
  EXPECT_THROW(WsClient("127.0.0.1", server().port(), "/chat"), boost::system::system_error);
}

// A suite of its own: after it, this address is held back for wrong tokens.
using AgentTokenLimit = AgentLink;

TEST_F(AgentTokenLimit, WrongTokensFromOneAddressAreHeldBackAndGoodOnesWait) {
  int refused = 0;
  for (; refused < 20; ++refused) {
    auto ws = connect();
    ws->send_text(hello("guess-" + std::to_string(refused)));
    const auto event = ws->read();
    ASSERT_TRUE(event.closed);
    if (event.close_code == 1013) {
      EXPECT_EQ(event.close_reason.rfind("too many wrong station tokens from 127.0.0.1; try "
                                         "again in ",
                                         0),
                0u)
          << event.close_reason;
      break;
    }
    ASSERT_EQ(event.close_code, 1008) << event.error;
    ASSERT_EQ(event.close_reason, "unknown station token");
  }
  EXPECT_EQ(refused, 11);
  // A good token from the held address waits too (and is told to retry): a valid token of one's
  // own station must not reset the count.
  auto ws = connect();
  ws->send_text(hello(kStationToken));
  EXPECT_EQ(ws->read().close_code, 1013);
  // The REST API and the rest of the server are untouched.
  EXPECT_EQ(as(kTrainee).get("/api/stations").status, 200);
}

}  // namespace
}  // namespace incise::server::test
