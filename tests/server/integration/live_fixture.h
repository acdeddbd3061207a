#pragma once
// Live sessions with the real server and the real incise-agent: a viewer of the view WebSocket
// that acknowledges frames like the dashboard, the demo stations, and a fixture that books a
// station, starts its agent and a session, and reads the database file directly.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "db_snapshot.h"
#include "server_fixture.h"
#include "tests/support/ws_client.h"

namespace incise::server::test {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

// One binary frame of the view WebSocket: number, size and simulated time, then the JPEG.
struct Frame {
  std::uint32_t number = 0;
  int width = 0;
  int height = 0;
  double sim_time_s = 0;
  std::vector<std::uint8_t> jpeg;
};

inline std::optional<Frame> parse_frame(const std::string& message) {
  if (message.size() < 16) return std::nullopt;
  Frame f;
  std::uint16_t w = 0, h = 0;
  std::memcpy(&f.number, message.data(), 4);
  std::memcpy(&w, message.data() + 4, 2);
  std::memcpy(&h, message.data() + 6, 2);
  std::memcpy(&f.sim_time_s, message.data() + 8, 8);
  f.width = w;
  f.height = h;
  f.jpeg.assign(message.begin() + 16, message.end());
  return f;
}

// A viewer that acknowledges every frame, like the dashboard does.
class Viewer {
 public:
  Viewer(unsigned short port, const std::string& target, const std::string& cookie)
      : ws_("127.0.0.1", port, target, {{"Cookie", "incise_session=" + cookie}}) {}

  // Reads until `done` returns true for an event or `timeout` passes. Returns whether done.
  template <class Done>
  bool read_until(Done done, std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (Clock::now() < deadline) {
      const auto event = ws_.read();
      if (event.closed) {
        closed = event;
        return done();
      }
      if (event.text) {
        auto message = nlohmann::json::parse(event.message);
        if (message["type"] == "metrics") metrics = message;
        if (message["type"] == "ended") ended = message;
      } else if (auto frame = parse_frame(event.message)) {
        ws_.send_text(nlohmann::json{{"type", "ack"}, {"frame", frame->number}}.dump());
        frames.push_back(std::move(*frame));
      }
      if (done()) return true;
    }
    return false;
  }
  void send(const nlohmann::json& message) { ws_.send_text(message.dump()); }
  void send_raw(const std::string& text) { ws_.send_text(text); }

  std::vector<Frame> frames;
  nlohmann::json metrics;
  std::optional<nlohmann::json> ended;
  std::optional<WsEvent> closed;

 private:
  WsClient ws_;
};

// The demo data's stations: Station 1 (the palpation bench) and the surgical station (scalpel and
// grasper).
struct Station {
  int id = 1;
  const char* token = kStationToken;
};
constexpr Station kBench{1, kStationToken};
constexpr Station kSurgical{2, "incise-demo-surgical-station-token"};

class LiveSession : public ServerTest {
 protected:
  // Who books, starts, stops and watches by default: the demo trainee; a test of a task that
  // palpation unlocks sets the resident, who has mastered it (the server refuses locked tasks).
  Login trainee_ = kTrainee;

  // The real agent for a station (Station 1 unless said); extra arguments (devices) after the
  // defaults, and the port it connects to (the server's unless a proxy sits between).
  std::unique_ptr<ChildProcess> start_agent(std::vector<std::string> extra = {}, int port = 0,
                                            Station station = kBench) {
    std::vector<std::string> args = {
        INCISE_AGENT_BIN, "--server",
        "ws://127.0.0.1:" + std::to_string(port ? port : server().port()) + "/agent", "--rate",
        "500"};
    args.insert(args.end(), extra.begin(), extra.end());
    auto agent = std::make_unique<ChildProcess>(
        args, incise::test::environment_with("INCISE_STATION_TOKEN", station.token));
    const auto deadline = Clock::now() + 5s;
    while (Clock::now() < deadline && !station_online(station.id))
      std::this_thread::sleep_for(20ms);
    return agent;
  }

  bool station_online(int station_id = kBench.id) {
    for (const auto& s : as(trainee_).get("/api/stations").json()) {
      if (s["id"] == station_id) return s["online"].get<bool>();
    }
    return false;
  }

  // A booking of a station for the trainee covering now (the quarter hour in progress).
  std::int64_t book_now(int station_id = kBench.id) {
    const auto now = std::chrono::duration_cast<std::chrono::seconds>(
                         std::chrono::system_clock::now().time_since_epoch())
                         .count();
    const auto start = now - now % 900;
    const auto response = as(trainee_).post("/api/bookings", {{"station_id", station_id},
                                                              {"starts_at", utc_text(start)},
                                                              {"ends_at", utc_text(start + 3600)}});
    EXPECT_EQ(response.status, 201) << response.body;
    return response.json().value("id", 0);
  }

  void cancel(std::int64_t booking) {
    as(trainee_).del("/api/bookings/" + std::to_string(booking));
  }

  // The real agent for Station 1, a trainee's booking covering now, and a running session on it.
  struct Running {
    std::unique_ptr<ChildProcess> agent;
    std::int64_t booking = 0;
    std::int64_t session = 0;
    std::int64_t recording = 0;
  };
  void start_booked_session(Running& out, const std::string& task = "palpation",
                            std::vector<std::string> agent_args = {}, int agent_port = 0,
                            Station station = kBench) {
    out.agent = start_agent(std::move(agent_args), agent_port, station);
    ASSERT_TRUE(station_online(station.id)) << out.agent->stderr_text();
    out.booking = book_now(station.id);
    const auto started =
        as(trainee_).post("/api/sessions", {{"station_id", station.id}, {"task", task}});
    ASSERT_EQ(started.status, 201) << started.body;
    EXPECT_EQ(started.json()["live"]["state"], "running");
    out.session = started.json()["id"].get<std::int64_t>();
    out.recording = started.json()["live"]["recording_id"].get<std::int64_t>();
  }

  // Stops the run's session and cancels its booking however the test ends, so that a failure
  // does not leave Station 1 busy for the next test.
  struct EndRun {
    LiveSession& test;
    const Running& run;
    ~EndRun() {
      test.as(test.trainee_)
          .post("/api/sessions/" + std::to_string(run.session) + "/stop", nlohmann::json::object());
      test.cancel(run.booking);
    }
  };

  std::string cookie(const Login& login) { return *as(login).cookie("incise_session"); }

  std::unique_ptr<Viewer> view(const std::string& target) { return view(target, trainee_); }
  std::unique_ptr<Viewer> view(const std::string& target, const Login& login) {
    return std::make_unique<Viewer>(server().port(), target, cookie(login));
  }

  static std::string db_text(const std::string& sql) {
    return query_text(server().database(), sql);
  }
};

}  // namespace incise::server::test
