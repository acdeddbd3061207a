// The incise-agent executable (devices/agent/), run as a process against an in-test server.

#include <signal.h>

#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include <chrono>
#include <functional>
#include <regex>
#include <thread>

#include "agent_process.h"
#include "devices/protocol.h"
#include "fake_station_server.h"

namespace incise::devices::agent::testing {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

bool wait_until(const std::function<bool()>& condition, Clock::duration timeout) {
  const auto deadline = Clock::now() + timeout;
  while (!condition()) {
    if (Clock::now() >= deadline) return false;
    std::this_thread::sleep_for(10ms);
  }
  return true;
}

// A port on which nothing listens (bound, then released, so the OS will not hand it out again
// right away).
unsigned short unused_port() {
  boost::asio::io_context io;
  boost::asio::ip::tcp::acceptor acceptor(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  return acceptor.local_endpoint().port();
}

// Frames of one connection: decoded cleanly, sequence 0, 1, 2, ..., timestamps increasing.
void expect_clean_stream(const FakeStationRecord& record, int connection) {
  uint32_t expected_sequence = 0;
  uint64_t last_timestamp = 0;
  for (const ReceivedFrame& frame : record.frames) {
    if (frame.connection != connection) continue;
    EXPECT_EQ(frame.sequence, expected_sequence++);
    if (frame.sequence > 0) {
      EXPECT_GT(frame.timestamp_us, last_timestamp);
    }
    last_timestamp = frame.timestamp_us;
  }
  EXPECT_GT(expected_sequence, 0u) << "no frames on connection " << connection;
}

std::size_t frame_count(const FakeStationServer& server) {
  return server.record().frames.size();
}

TEST(Agent, StreamsDeviceStatesAtTheRateAndStopsCleanlyOnSigterm) {
  FakeStationServer server;
  AgentProcess agent({"--server", server.url(), "--rate", "250", "--no-deadband"},
                     {"INCISE_STATION_TOKEN=good-token"});
  ASSERT_TRUE(wait_until([&] { return frame_count(server) >= 1; }, 5s)) << agent.stderr_text();

  const auto start = Clock::now();
  const std::size_t before = frame_count(server);
  std::this_thread::sleep_for(1s);
  const std::size_t after = frame_count(server);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const double rate = (after - before) / seconds;
  EXPECT_GE(rate, 125.0);  // the machine is noisy: half the requested rate
  EXPECT_LE(rate, 300.0);  // but never a burst above it

  const auto signalled = Clock::now();
  agent.send_signal(SIGTERM);
  EXPECT_EQ(agent.wait_for_exit(2s), std::optional<int>(0)) << agent.stderr_text();
  EXPECT_LT(Clock::now() - signalled, 1s);

  ASSERT_TRUE(wait_until([&] { return !server.record().agent_close_codes.empty(); }, 1s));
  const FakeStationRecord record = server.record();
  EXPECT_EQ(record.agent_close_codes, std::vector<int>{1000});  // a normal close
  EXPECT_TRUE(record.errors.empty()) << record.errors.front();
  EXPECT_EQ(record.connections, 1);
  ASSERT_EQ(record.agents.size(), 1u);
  EXPECT_TRUE(record.agents[0].starts_with("incise-agent/")) << record.agents[0];
  expect_clean_stream(record, 1);

  const std::string log = agent.stderr_text();
  EXPECT_NE(log.find("incise-agent: connected to " + server.url() + " as station 7 \"Bench 7\""),
            std::string::npos)
      << log;
  // Every frame the agent counts as sent arrived.
  EXPECT_NE(log.find("incise-agent: stopped: sent " + std::to_string(record.frames.size()) +
                     " device states over 1 connection, connected "),
            std::string::npos)
      << log;
}

TEST(Agent, LogsSessionNoticesAndStatisticsOnSigusr1AndAtExit) {
  ForceModel model;
  model.force = {0.0, 0.0, 1.0};
  FakeStationBehaviour behaviour;
  behaviour.force_model = model;
  behaviour.session_notice = build_session_notice({3, "running"});
  FakeStationServer server(behaviour);
  AgentProcess agent({"--server", server.url()}, {"INCISE_STATION_TOKEN=good-token"});
  // 60 written: at least the first 50 have been read by the time the agent stops (a few may
  // still be on the way when the server counts them).
  ASSERT_TRUE(wait_until([&] { return server.record().models_sent >= 60; }, 5s))
      << agent.stderr_text();
  const auto stats_lines = [&] {
    const std::string log = agent.stderr_text();
    std::size_t count = 0;
    for (auto at = log.find("incise-agent: stats: loop "); at != std::string::npos;
         at = log.find("incise-agent: stats: loop ", at + 1)) {
      ++count;
    }
    return count;
  };
  EXPECT_EQ(stats_lines(), 0u);
  agent.send_signal(SIGUSR1);
  ASSERT_TRUE(wait_until([&] { return stats_lines() == 1; }, 2s)) << agent.stderr_text();
  agent.send_signal(SIGTERM);
  EXPECT_EQ(agent.wait_for_exit(2s), std::optional<int>(0)) << agent.stderr_text();
  EXPECT_EQ(stats_lines(), 2u);

  const std::string log = agent.stderr_text();
  EXPECT_NE(log.find("incise-agent: session 3 running\n"), std::string::npos) << log;
  EXPECT_NE(log.find("haptic loop at 1000 Hz, sending states at 500 Hz (deadband on)"),
            std::string::npos)
      << log;
  // The exit line: the loop's figures, then round trip and counts that match the server's.
  std::smatch m;
  const std::regex line(
      "stats: loop ([0-9.]+) Hz, period p50 ([0-9]+) us p99 ([0-9]+) us, max jitter ([0-9]+) us, "
      "([0-9]+) overruns; round trip p50 ([0-9.]+) ms p99 ([0-9.]+) ms \\(([0-9]+) models\\); "
      "states sent ([0-9]+), dropped ([0-9]+); force models received ([0-9]+), lost ([0-9]+); "
      "states held by the deadband ([0-9]+)\n"
      "incise-agent: stopped:");
  ASSERT_TRUE(std::regex_search(log, m, line)) << log;
  EXPECT_NEAR(std::stod(m[1]), 1000.0, 100.0);
  const FakeStationRecord record = server.record();
  EXPECT_EQ(std::stoul(m[9]), record.frames.size());
  // Models the server wrote while the agent was closing may never have been read.
  const unsigned long received = std::stoul(m[11]);
  EXPECT_LE(received, static_cast<unsigned long>(record.models_sent));
  EXPECT_GE(received, 50u);
  EXPECT_EQ(std::stoul(m[8]), received);  // every model echoed one of the agent's states
  EXPECT_GT(std::stod(m[7]), 0.0);
}

TEST(Agent, ExitsWithThreeWhenTheServerRefusesTheToken) {
  FakeStationServer server;
  AgentProcess agent({"--server", server.url()}, {"INCISE_STATION_TOKEN=wrong-token"});
  EXPECT_EQ(agent.wait_for_exit(5s), std::optional<int>(3)) << agent.stderr_text();
  EXPECT_NE(agent.stderr_text().find("incise-agent: server refused: unknown station token\n"),
            std::string::npos)
      << agent.stderr_text();
  const FakeStationRecord record = server.record();
  EXPECT_EQ(record.connections, 1);  // no retry with a refused token
  EXPECT_TRUE(record.frames.empty());
}

TEST(Agent, ReconnectsAfterTheServerDropsTheLink) {
  FakeStationBehaviour behaviour;
  behaviour.drop_first_connection_after = 10;
  FakeStationServer server(behaviour);
  AgentProcess agent({"--server", server.url(), "--rate", "250"},
                     {"INCISE_STATION_TOKEN=good-token"});
  const auto on_second = [&] {
    int count = 0;
    for (const auto& frame : server.record().frames)
      count += frame.connection == 2;
    return count;
  };
  ASSERT_TRUE(wait_until([&] { return on_second() >= 5; }, 5s)) << agent.stderr_text();
  agent.send_signal(SIGINT);
  EXPECT_EQ(agent.wait_for_exit(2s), std::optional<int>(0)) << agent.stderr_text();

  const FakeStationRecord record = server.record();
  EXPECT_EQ(record.connections, 2);
  EXPECT_TRUE(record.errors.empty()) << record.errors.front();
  expect_clean_stream(record, 1);
  expect_clean_stream(record, 2);  // each connection numbers its frames from 0
  const std::string log = agent.stderr_text();
  EXPECT_TRUE(std::regex_search(log, std::regex("incise-agent: link lost after [0-9.]+ s: server "
                                                "closed the connection \\(1001 \"test drops the "
                                                "link\"\\); reconnecting in 0.25 s\n")))
      << log;
  EXPECT_NE(log.find("over 2 connections"), std::string::npos) << log;
}

TEST(Agent, BacksOffWhileNoServerListensAndStopsDuringTheWait) {
  const std::string url = "ws://127.0.0.1:" + std::to_string(unused_port()) + "/agent";
  AgentProcess agent({"--server", url}, {"INCISE_STATION_TOKEN=t"});
  const auto retry_line = [&](int attempt, const char* delay) {
    return "incise-agent: connection attempt " + std::to_string(attempt) + " to " + url +
           " failed: connect: Connection refused; retrying in " + delay + "\n";
  };
  ASSERT_TRUE(wait_until(
      [&] { return agent.stderr_text().find(retry_line(2, "0.5 s")) != std::string::npos; }, 3s))
      << agent.stderr_text();
  EXPECT_NE(agent.stderr_text().find(retry_line(1, "0.25 s")), std::string::npos);

  const auto signalled = Clock::now();
  agent.send_signal(SIGTERM);
  EXPECT_EQ(agent.wait_for_exit(2s), std::optional<int>(0)) << agent.stderr_text();
  EXPECT_LT(Clock::now() - signalled, 1s);
  EXPECT_NE(agent.stderr_text().find("stopped: sent 0 device states over 0 connections"),
            std::string::npos);
}

TEST(Agent, CommandLine) {
  {
    AgentProcess help({"--help"});
    EXPECT_EQ(help.wait_for_exit(2s), std::optional<int>(0));
    EXPECT_NE(help.stdout_text().find("--server URL"), std::string::npos);
  }
  const std::pair<std::vector<std::string>, std::string> bad[] = {
      {{"--bogus"}, "incise-agent: unknown option '--bogus' (see --help)\n"},
      {{"--server", "http://x/agent"},
       "incise-agent: --server http://x/agent: must start with ws:// or wss:// (see --help)\n"},
      {{"--rate", "fast"},
       "incise-agent: --rate fast: must be a number of Hz in [250, 1000] (see --help)\n"},
      {{"--rate", "200"},
       "incise-agent: --rate 200: must be a number of Hz in [250, 1000] (see --help)\n"},
      {{"--rate", "1001"},
       "incise-agent: --rate 1001: must be a number of Hz in [250, 1000] (see --help)\n"},
      {{"--token", "t"},
       "incise-agent: --token on the command line is refused (any local user can read it in ps): "
       "set INCISE_STATION_TOKEN or put token = ... in the --config file (see --help)\n"},
      {{"--script", "/nonexistent/script.json"},
       "incise-agent: simulated /nonexistent/script.json: cannot open\n"},
      {{"--device", "bogus"},
       "incise-agent: --device bogus: unknown driver (have simulated, hand, scope, knee-scope, "
       "knee-instrument, replay, evdev)\n"},
      {{"--device", "knee-scope"},
       "incise-agent: knee-scope: needs a script (knee-scope:SCRIPT.json)\n"},
      {{"--device", "simulated", "--device", "hand", "--device", "simulated"},
       "incise-agent: --device simulated: a station has at most 2 devices (see --help)\n"},
      {{"--device", "replay:/nonexistent.log"},
       "incise-agent: replay /nonexistent.log: cannot open\n"},
      {{"--max-force", "50"},
       "incise-agent: --max-force 50: must be a number of N in (0, 40] (see --help)\n"},
      {{"--config", "/nonexistent.conf"}, "incise-agent: config /nonexistent.conf: cannot open\n"},
  };
  {
    AgentProcess agent({});
    EXPECT_EQ(agent.wait_for_exit(2s), std::optional<int>(2));
    EXPECT_EQ(agent.stderr_text(),
              "incise-agent: no station token: set INCISE_STATION_TOKEN or put token = ... in the "
              "--config file (see --help)\n");
  }
  for (const auto& [args, message] : bad) {
    AgentProcess agent(args, {"INCISE_STATION_TOKEN=t"});
    EXPECT_EQ(agent.wait_for_exit(2s), std::optional<int>(2)) << message;
    EXPECT_EQ(agent.stderr_text(), message);
  }
}

}  // namespace
}  // namespace incise::devices::agent::testing
