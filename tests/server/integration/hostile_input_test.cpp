// Requests that once stopped the whole server, sent to the real server binary while a trainee's
// live session runs: bytes that are not UTF-8 in a path, a static file's path, a WebSocket
// upgrade's target and a login body; numbers beyond a double's range in the agent's hello, in view
// and replay messages and in REST bodies. Each gets its precise answer (400/422 with a JSON body,
// or a 1007/1008 close with a short valid reason), and after each the server still answers and
// the live session runs on undisturbed: time advancing, its agent online, its viewer served.
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "live_fixture.h"
#include "server/replay_slots.h"
#include "tests/support/hostile_json.h"

namespace incise::server::test {
namespace {

// Sends `bytes` on a new TCP connection and returns everything the server sends back until it
// closes the connection or 5 s pass: what `printf ... | nc 127.0.0.1 PORT` shows.
std::string raw_exchange(unsigned short port, const std::string& bytes) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return "socket failed";
  timeval timeout{5, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::string reply;
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
      ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size())) {
    ::shutdown(fd, SHUT_WR);  // as nc does at the end of its input
    char buffer[4096];
    for (ssize_t n; (n = ::recv(fd, buffer, sizeof buffer, 0)) > 0;)
      reply.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return reply;
}

// `bytes` for a test's trace: bytes outside printable ASCII as \xNN.
std::string printable(const std::string& bytes) {
  std::string out;
  for (const char c : bytes) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7F) {
      out += c;
    } else {
      constexpr char kHex[] = "0123456789ABCDEF";
      out += {'\\', 'x', kHex[byte >> 4], kHex[byte & 15]};
    }
  }
  return out;
}

// The status code and the JSON body of a raw HTTP/1.1 reply.
struct RawReply {
  int status = 0;
  nlohmann::json body;
};
RawReply parse_reply(const std::string& reply) {
  RawReply out;
  if (reply.rfind("HTTP/1.1 ", 0) == 0) out.status = std::atoi(reply.c_str() + 9);
  const auto body = reply.find("\r\n\r\n");
  if (body != std::string::npos) {
    out.body = nlohmann::json::parse(reply.substr(body + 4), nullptr, false);
  }
  return out;
}

class HostileInput : public LiveSession {
 protected:
  // The server process is alive and answers, and the session runs on: not paused, its agent
  // online, its simulated time further on than at the previous check.
  void expect_undisturbed(const std::string& after) {
    SCOPED_TRACE("after " + after);
    ASSERT_TRUE(server().process().running()) << server().process().stderr_text();
    auto client = new_client();
    ASSERT_EQ(client->get("/api/health").status, 200);
    std::this_thread::sleep_for(100ms);
    const auto live = as(kTrainee).get(session_path_).json()["live"];
    EXPECT_EQ(live["state"], "running");
    EXPECT_TRUE(live["agent_online"].get<bool>());
    const double t = live["sim_time_s"].get<double>();
    EXPECT_GT(t, sim_time_s_) << live.dump();
    sim_time_s_ = t;
  }

  // Whether `response` is `status` with a JSON error whose text is valid UTF-8.
  static ::testing::AssertionResult is_clean_error(const RawReply& reply, int status) {
    if (reply.status != status) {
      return ::testing::AssertionFailure() << "status " << reply.status << ", expected " << status;
    }
    if (!reply.body.is_object() || !reply.body["error"].is_string()) {
      return ::testing::AssertionFailure() << "no JSON error body";
    }
    return ::testing::AssertionSuccess() << reply.body["error"].get<std::string>();
  }

  std::string session_path_;
  double sim_time_s_ = 0;
};

// Every response, API, static or error, carries the browser hardening headers; an HTTP/1.1
// request without Host is refused (the origin checks compare against it).
TEST_F(HostileInput, EveryResponseIsHardenedAndARequestWithoutHostIs400) {
  const auto port = server().port();
  for (const std::string request :
       {"GET /api/health HTTP/1.1\r\nHost: x\r\n\r\n", "GET / HTTP/1.1\r\nHost: x\r\n\r\n",
        "GET /api/nothing HTTP/1.1\r\nHost: x\r\n\r\n", "GET /api/\xff HTTP/1.1\r\nHost: x\r\n\r\n",
        "GET /api/health HTTP/1.1\r\n\r\n"}) {
    SCOPED_TRACE(printable(request));
    const auto reply = raw_exchange(port, request);
    const auto head = reply.substr(0, reply.find("\r\n\r\n"));
    EXPECT_NE(head.find("\r\nContent-Security-Policy: default-src 'self'; script-src 'self';"),
              std::string::npos)
        << head;
    EXPECT_NE(head.find("frame-ancestors 'none'"), std::string::npos);
    EXPECT_NE(head.find("\r\nX-Frame-Options: DENY"), std::string::npos);
    EXPECT_NE(head.find("\r\nX-Content-Type-Options: nosniff"), std::string::npos);
    EXPECT_NE(head.find("\r\nReferrer-Policy: no-referrer"), std::string::npos);
  }
  const auto no_host = parse_reply(raw_exchange(port, "GET /api/health HTTP/1.1\r\n\r\n"));
  EXPECT_TRUE(is_clean_error(no_host, 400));
  EXPECT_EQ(no_host.body.value("error", ""), "a Host header is required (HTTP/1.1)");
  // HTTP/1.0 has no Host requirement.
  EXPECT_EQ(raw_exchange(port, "GET /api/health HTTP/1.0\r\n\r\n").rfind("HTTP/1.0 200", 0), 0u);
}

TEST_F(HostileInput, NothingAClientSendsStopsTheServerOrDisturbsALiveSession) {
  Running run;
  ASSERT_NO_FATAL_FAILURE(start_booked_session(run));
  session_path_ = "/api/sessions/" + std::to_string(run.session);
  auto watcher = view(session_path_ + "/view?fps=10&width=160&height=120");
  ASSERT_TRUE(watcher->read_until([&] { return watcher->frames.size() >= 2; }, 10s));
  ASSERT_NO_FATAL_FAILURE(expect_undisturbed("the start"));
  const auto port = server().port();

  // Bytes that are not UTF-8 in the request target: the API, a static file, an upgrade.
  const std::string targets[] = {"/api/\xff", "/\xff.js", "/assets/\xc0\xaf",
                                 "/api/sessions/\xff/view", "/agent\xed\xa0\x80"};
  for (const auto& target : targets) {
    const auto reply =
        parse_reply(raw_exchange(port, "GET " + target + " HTTP/1.1\r\nHost: x\r\n\r\n"));
    EXPECT_TRUE(is_clean_error(reply, 400)) << target;
    if (reply.body.is_object()) {
      EXPECT_EQ(reply.body.value("error", ""),
                "the request target must be printable ASCII (percent-encode other bytes)");
    }
    ASSERT_NO_FATAL_FAILURE(expect_undisturbed("GET " + printable(target)));
  }
  const auto upgrade = parse_reply(
      raw_exchange(port,
                   "GET /api/sessions/\xff/view HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\n"
                   "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                   "Sec-WebSocket-Version: 13\r\n\r\n"));
  EXPECT_TRUE(is_clean_error(upgrade, 400));
  ASSERT_NO_FATAL_FAILURE(expect_undisturbed("a WebSocket upgrade to a bad target"));

  // Hostile values in a login body (nobody logged in) and in a logged-in trainee's REST body.
  for (const auto& value : incise::test::hostile_values()) {
    auto client = new_client();
    const auto login = client->request(
        http::verb::post, "/api/login",
        incise::test::with_value(R"({"username": @, "password": "x"})", value.token),
        {{"Content-Type", "application/json"}});
    EXPECT_TRUE(is_error(login, value.number ? 422 : 400)) << value.what;
    const auto booking = as(kTrainee).request(
        http::verb::post, "/api/bookings",
        incise::test::with_value(R"({"station_id": @, "starts_at": "x", "ends_at": "y"})",
                                 value.token),
        {{"Content-Type", "application/json"}});
    EXPECT_TRUE(is_error(booking, value.number ? 422 : 400)) << value.what;
    ASSERT_NO_FATAL_FAILURE(expect_undisturbed("a body with " + value.what));
  }

  // The agent's hello, before any token is checked.
  const std::pair<std::string, int> hellos[] = {
      {R"({"type": "hello", "protocol": 1e400, "station_token": "t", "agent": "a"})", 1008},
      {R"({"type": "hello", "protocol": 1, "station_token": "\ud800", "agent": "a"})", 1008},
      // Not UTF-8 in a text frame: Beast refuses the frame itself.
      {"{\"type\": \"hello\", \"protocol\": 1, \"station_token\": \"\xff\", \"agent\": \"a\"}",
       1007},
  };
  for (const auto& [hello, code] : hellos) {
    WsClient agent("127.0.0.1", port);
    agent.send_text(hello);
    const auto closed = agent.read();
    ASSERT_TRUE(closed.closed) << hello;
    EXPECT_EQ(closed.close_code, code) << hello;
    EXPECT_TRUE(incise::test::is_utf8(closed.close_reason));
    EXPECT_LE(closed.close_reason.size(), 123u);
    ASSERT_NO_FATAL_FAILURE(expect_undisturbed("a hello of " + printable(hello)));
  }
  WsClient bad_hello("127.0.0.1", port);
  bad_hello.send_text(hellos[0].first);
  EXPECT_EQ(bad_hello.read().close_reason,
            "hello: not valid JSON (a number beyond the range of a double)");

  // A second viewer's messages: each closes that viewer alone.
  const std::string view_messages[] = {
      R"({"type": "configure", "fps": 1e400})", R"({"type": "ack", "frame": -1e400})",
      R"({"type": "configure", "width": "\udc00"})", R"({"type": "seek", "t": 1e400})"};
  for (const auto& message : view_messages) {
    WsClient viewer("127.0.0.1", port, session_path_ + "/view",
                    {{"Cookie", "incise_session=" + cookie(kTrainee)}});
    viewer.send_text(message);
    WsEvent event = viewer.read();
    for (int i = 0; i < 200 && !event.closed; ++i)
      event = viewer.read();  // metrics and frames until the close
    ASSERT_TRUE(event.closed) << message;
    EXPECT_EQ(event.close_code, 1007) << message;
    EXPECT_TRUE(event.close_reason.starts_with("malformed JSON: ")) << event.close_reason;
    EXPECT_TRUE(incise::test::is_utf8(event.close_reason));
    ASSERT_NO_FATAL_FAILURE(expect_undisturbed(message));
  }
  // The first viewer was served all along.
  const auto frames = watcher->frames.size();
  EXPECT_TRUE(watcher->read_until([&] { return watcher->frames.size() >= frames + 3; }, 5s));
  EXPECT_FALSE(watcher->closed.has_value());

  // The session ends as any other: stopped, recorded, scored.
  const auto stopped = as(kTrainee).post(session_path_ + "/stop", nlohmann::json::object());
  ASSERT_EQ(stopped.status, 200) << stopped.body;
  EXPECT_EQ(stopped.json()["state"], "finished");
  const auto rid = std::to_string(run.recording);
  EXPECT_EQ(db_text("SELECT state FROM recordings WHERE id = " + rid), "complete");
  EXPECT_GT(db_int("SELECT COUNT(*) FROM scores WHERE session_id = " + std::to_string(run.session)),
            0);
  if (server().database().dialect == db::Dialect::sqlite) {
    EXPECT_EQ(db_text("PRAGMA integrity_check"), "ok");
  }

  // Its replay: hostile controls close that replay; another replay of it plays.
  const auto replay_path = "/api/recordings/" + rid + "/replay?fps=10&width=160&height=120";
  for (const char* message :
       {R"({"type": "seek", "t": 1e400})", R"({"type": "speed", "value": -1e400})",
        R"({"type": "speed", "value": "\ud800\u0041"})"}) {
    auto replay = view(replay_path, kInstructor);
    replay->send_raw(message);
    ASSERT_TRUE(replay->read_until([&] { return replay->closed.has_value(); }, 10s)) << message;
    EXPECT_EQ(replay->closed->close_code, 1007);
    EXPECT_TRUE(replay->closed->close_reason.starts_with("malformed JSON: "))
        << replay->closed->close_reason;
  }
  auto replay = view(replay_path, kInstructor);
  replay->send({{"type", "play"}});
  EXPECT_TRUE(replay->read_until([&] { return replay->frames.size() >= 3; }, 10s));

  // Replays are bounded per viewer (each is a simulation and a renderer): the instructor's
  // fourth is closed with 1013 and a reason the page shows; closing one frees its slot.
  const int per_user = ReplaySlots::kDefaultPerUser;
  std::vector<std::unique_ptr<Viewer>> more;
  for (int i = 1; i < per_user; ++i) {
    more.push_back(view(replay_path, kInstructor));
    ASSERT_TRUE(more.back()->read_until([&] { return !more.back()->frames.empty(); }, 10s)) << i;
  }
  auto refused = view(replay_path, kInstructor);
  ASSERT_TRUE(refused->read_until([&] { return refused->closed.has_value(); }, 10s));
  EXPECT_EQ(refused->closed->close_code, 1013);
  EXPECT_EQ(refused->closed->close_reason, "you have " + std::to_string(per_user) +
                                               " replays open already; close one to open another");
  // Another viewer is not held back by the instructor's share.
  auto trainees = view(replay_path, kTrainee);
  EXPECT_TRUE(trainees->read_until([&] { return !trainees->frames.empty(); }, 10s));
  more.clear();
  bool reopened = false;
  for (int attempt = 0; attempt < 50 && !reopened; ++attempt) {
    auto again = view(replay_path, kInstructor);
    reopened = again->read_until([&] { return !again->frames.empty() || again->closed; }, 10s) &&
               !again->closed;
    if (!reopened) std::this_thread::sleep_for(100ms);
  }
  EXPECT_TRUE(reopened);
  EXPECT_TRUE(server().process().running());
  cancel(run.booking);
}

}  // namespace
}  // namespace incise::server::test
