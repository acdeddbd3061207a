// JSON control messages: devices/control_messages.cpp (declared in devices/protocol.h).

#include <gtest/gtest.h>

#include <functional>
#include <utility>

#include <nlohmann/json.hpp>

#include "devices/protocol.h"
#include "tests/support/hostile_json.h"

namespace incise::devices {
namespace {

using nlohmann::json;

std::string hello_error(const json& message) {
  const auto parsed = parse_hello(message.dump());
  EXPECT_FALSE(parsed);
  EXPECT_LE(parsed.error.size(), kMaxCloseReasonSize);
  return parsed.error;
}

std::string welcome_error(const json& message) {
  const auto parsed = parse_welcome(message.dump());
  EXPECT_FALSE(parsed);
  EXPECT_LE(parsed.error.size(), kMaxCloseReasonSize);
  return parsed.error;
}

json good_hello() {
  return {{"type", "hello"}, {"protocol", 1}, {"station_token", "tok-123"}, {"agent", "a/1"}};
}

json good_welcome() {
  return {{"type", "welcome"}, {"protocol", 1}, {"station_id", 3}, {"station_name", "Bench 3"}};
}

TEST(ControlMessages, HelloRoundTrip) {
  const Hello hello{"s3cr3t \"quoted\" \\ token", "incise-agent/0.1.0 (simulated)"};
  const std::string text = build_hello(hello);
  const auto parsed = parse_hello(text);
  ASSERT_TRUE(parsed) << parsed.error;
  EXPECT_EQ(*parsed.value, hello);

  // The exact shape docs/api.md promises.
  const json j = json::parse(text);
  EXPECT_EQ(j, (json{{"type", "hello"},
                     {"protocol", 1},
                     {"station_token", hello.station_token},
                     {"agent", hello.agent}}));
}

TEST(ControlMessages, WelcomeRoundTrip) {
  const Welcome welcome{9007199254740993, "Übungsplatz 2 — left", ""};
  const std::string text = build_welcome(welcome);
  const auto parsed = parse_welcome(text);
  ASSERT_TRUE(parsed) << parsed.error;
  EXPECT_EQ(*parsed.value, welcome);
  const json j = json::parse(text);
  EXPECT_EQ(j, (json{{"type", "welcome"},
                     {"protocol", 1},
                     {"station_id", welcome.station_id},
                     {"station_name", welcome.station_name}}));
}

TEST(ControlMessages, WelcomeCarriesTheCalibrationAndItsNoticeRoundTrips) {
  const std::string calibration = R"({"devices":[{"index":0,"kind":"pen"}]})";
  const Welcome welcome{3, "Bench 3", calibration};
  const auto parsed = parse_welcome(build_welcome(welcome));
  ASSERT_TRUE(parsed) << parsed.error;
  EXPECT_EQ(json::parse(parsed.value->calibration), json::parse(calibration));
  json bad = json::parse(build_welcome(welcome));
  bad["calibration"] = "pen";
  EXPECT_EQ(parse_welcome(bad.dump()).error,
            "welcome: \"calibration\" must be an object, got string");

  const auto notice = parse_calibration_notice(build_calibration_notice(calibration));
  ASSERT_TRUE(notice) << notice.error;
  EXPECT_EQ(json::parse(*notice.value), json::parse(calibration));
  EXPECT_EQ(message_type(build_calibration_notice(calibration)), "calibration");
  EXPECT_EQ(parse_calibration_notice(R"({"type":"calibration"})").error,
            "calibration: \"calibration\" must be an object");
}

TEST(ControlMessages, LinkReportRoundTripsAndBadFieldsAreNamed) {
  LinkReport report;
  report.loop_hz = 999.5;
  report.rtt_p50_ms = 1.25;
  report.rtt_p99_ms = 4.5;
  report.loss_down = 0.05;
  report.states_sent = 480;
  report.states_held = 20;
  report.devices = {{0, 3.5, "none", 1.5, 0.0, 0.25}, {1, 4.0, "stale model", 0.0, 2.0, 0.5}};
  const auto parsed = parse_link_report(build_link_report(report));
  ASSERT_TRUE(parsed) << parsed.error;
  EXPECT_EQ(*parsed.value, report);
  const std::pair<std::function<void(json&)>, std::string> bad[] = {
      {[](json& j) { j["loss_down"] = 1.5; }, "link: \"loss_down\" must be in [0, 1], got 1.5"},
      {[](json& j) { j.erase("rtt_p50_ms"); }, "link: missing key \"rtt_p50_ms\""},
      {[](json& j) { j["states_sent"] = -1; },
       "link: \"states_sent\" must be a non-negative integer, got -1"},
      {[](json& j) { j["devices"][1]["index"] = 2; },
       "link: devices[1]: \"index\" must be in [0, 1], got 2"},
      {[](json& j) { j["devices"].push_back(j["devices"][0]); },
       "link: \"devices\" has 3 entries, at most 2"},
      {[](json& j) { j["devices"][0]["force_n"] = "x"; },
       "link: devices[0]: \"force_n\" must be a number, got string"},
  };
  for (const auto& [change, message] : bad) {
    json j = json::parse(build_link_report(report));
    change(j);
    EXPECT_EQ(parse_link_report(j.dump()).error, message);
  }
}

TEST(ControlMessages, UnknownKeysAreIgnoredAndOrderDoesNotMatter) {
  EXPECT_TRUE(parse_hello(R"({"agent":"a","station_token":"t","protocol":1,"type":"hello",
                              "extra":{"anything":[1,2]}})"));
  json w = good_welcome();
  w["server"] = "incise/0.2";
  EXPECT_TRUE(parse_welcome(w.dump()));
}

TEST(ControlMessages, ProtocolVersionMismatchNamesBothVersions) {
  json hello = good_hello();
  hello["protocol"] = 2;
  EXPECT_EQ(hello_error(hello), "protocol 2 not supported (server speaks 1)");
  json welcome = good_welcome();
  welcome["protocol"] = 0;
  EXPECT_EQ(welcome_error(welcome), "protocol 0 not supported (agent speaks 1)");
  // The version is checked before the other keys: a newer peer may have renamed them.
  EXPECT_EQ(hello_error({{"type", "hello"}, {"protocol", 7}}),
            "protocol 7 not supported (server speaks 1)");
}

TEST(ControlMessages, HelloErrorsArePrecise) {
  EXPECT_EQ(hello_error(json::array()), "hello: expected a JSON object, got array");
  json h = good_hello();
  h.erase("type");
  EXPECT_EQ(hello_error(h), "hello: missing key \"type\"");
  h = good_hello();
  h.erase("protocol");
  EXPECT_EQ(hello_error(h), "hello: missing key \"protocol\"");
  h = good_hello();
  h["type"] = 5;
  EXPECT_EQ(hello_error(h), "hello: \"type\" must be a string, got number");
  h["type"] = "welcome";
  EXPECT_EQ(hello_error(h), "hello: \"type\" is \"welcome\", expected \"hello\"");
  h = good_hello();
  h["protocol"] = "1";
  EXPECT_EQ(hello_error(h), "hello: \"protocol\" must be an integer, got string");
  h["protocol"] = 1.5;
  EXPECT_EQ(hello_error(h), "hello: \"protocol\" must be an integer, got number");
  h = good_hello();
  h.erase("station_token");
  EXPECT_EQ(hello_error(h), "hello: missing key \"station_token\"");
  h["station_token"] = nullptr;
  EXPECT_EQ(hello_error(h), "hello: \"station_token\" must be a string, got null");
  h["station_token"] = "";
  EXPECT_EQ(hello_error(h), "hello: \"station_token\" is empty");
  h["station_token"] = std::string(257, 'x');
  EXPECT_EQ(hello_error(h), "hello: \"station_token\" is longer than 256 bytes");
  h = good_hello();
  h.erase("agent");
  EXPECT_EQ(hello_error(h), "hello: missing key \"agent\"");
}

TEST(ControlMessages, NotJsonReportsTheByte) {
  const auto parsed = parse_hello(R"({"type": "hello", )");
  ASSERT_FALSE(parsed);
  EXPECT_TRUE(parsed.error.starts_with("hello: not valid JSON (syntax error at byte "))
      << parsed.error;
  EXPECT_FALSE(parse_welcome(""));
}

TEST(ControlMessages, WelcomeErrorsArePrecise) {
  json w = good_welcome();
  w.erase("station_id");
  EXPECT_EQ(welcome_error(w), "welcome: missing key \"station_id\"");
  for (const json& bad : {json(0), json(-4), json(1.0)}) {
    w["station_id"] = bad;
    EXPECT_TRUE(welcome_error(w).starts_with("welcome: \"station_id\" must be a positive integer"));
  }
  w["station_id"] = "3";
  EXPECT_EQ(welcome_error(w), "welcome: \"station_id\" must be a positive integer, got string");
  w["station_id"] = 18446744073709551615ull;  // does not fit a rowid
  EXPECT_FALSE(parse_welcome(w.dump()));
  w = good_welcome();
  w.erase("station_name");
  EXPECT_EQ(welcome_error(w), "welcome: missing key \"station_name\"");
  w = good_welcome();
  w["type"] = "hello";
  EXPECT_EQ(welcome_error(w), "welcome: \"type\" is \"hello\", expected \"welcome\"");
}

TEST(ControlMessages, ErrorsFitACloseReasonEvenForHugeInput) {
  json h = good_hello();
  h["type"] = std::string(10000, 'x');
  EXPECT_EQ(hello_error(h), "hello: \"type\" is \"xxxxxxxxxxxxxxxxxxxxxxx..., expected \"hello\"");
  // Peers' strings are quoted as ASCII escapes, so a cut never splits a UTF-8 sequence.
  h["type"] = std::string(30, 'a') + "\u00fc";
  EXPECT_EQ(hello_error(h), "hello: \"type\" is \"aaaaaaaaaaaaaaaaaaaaaaa..., expected \"hello\"");
  h["type"] = "\u00fc\u00fc";
  EXPECT_EQ(hello_error(h), "hello: \"type\" is \"\\u00fc\\u00fc\", expected \"hello\"");
}

TEST(ControlMessages, SessionNoticeRoundTrip) {
  for (const SessionNotice& notice :
       {SessionNotice{3, "running"}, SessionNotice{9007199254740993, "paused"},
        SessionNotice{3, "idle"}, SessionNotice{0, "idle"}}) {
    const std::string text = build_session_notice(notice);
    const auto parsed = parse_session_notice(text);
    ASSERT_TRUE(parsed) << parsed.error;
    EXPECT_EQ(*parsed.value, notice);
    EXPECT_EQ(
        json::parse(text),
        (json{{"type", "session"}, {"session_id", notice.session_id}, {"state", notice.state}}));
  }
  // Extra keys from a newer server are ignored.
  const auto extended =
      parse_session_notice(R"({"state": "running", "task": "palpation", "type": "session",
                               "session_id": 4})");
  ASSERT_TRUE(extended) << extended.error;
  EXPECT_EQ(*extended.value, (SessionNotice{4, "running"}));
}

TEST(ControlMessages, SessionNoticeErrors) {
  const std::pair<const char*, const char*> bad[] = {
      {"{", "session: not valid JSON (syntax error at byte 2)"},
      {"[1]", "session: expected a JSON object, got array"},
      {R"({"session_id": 1, "state": "running"})", "session: missing key \"type\""},
      {R"({"type": "session", "state": "running"})", "session: missing key \"session_id\""},
      {R"({"type": "session", "session_id": 1})", "session: missing key \"state\""},
      {R"({"type": "welcome", "session_id": 1, "state": "running"})",
       "session: \"type\" is \"welcome\", expected \"session\""},
      {R"({"type": 5, "session_id": 1, "state": "running"})",
       "session: \"type\" must be a string, got number"},
      {R"({"type": "session", "session_id": 1, "state": "done"})",
       "session: \"state\" is \"done\", expected running, paused or idle"},
      {R"({"type": "session", "session_id": 1, "state": true})",
       "session: \"state\" must be a string, got boolean"},
      {R"({"type": "session", "session_id": -2, "state": "paused"})",
       "session: \"session_id\" must be a positive integer, got -2"},
      {R"({"type": "session", "session_id": "7", "state": "paused"})",
       "session: \"session_id\" must be a positive integer, got string"},
      {R"({"type": "session", "session_id": 1.5, "state": "paused"})",
       "session: \"session_id\" must be a positive integer, got number"},
      {R"({"type": "session", "session_id": 0, "state": "running"})",
       "session: \"session_id\" 0 (no session) needs state idle, got running"},
  };
  for (const auto& [text, error] : bad) {
    const auto parsed = parse_session_notice(text);
    EXPECT_FALSE(parsed) << text;
    EXPECT_EQ(parsed.error, error) << text;
  }
}

// Every message either side parses, with a hostile value in each of its fields: a failure whose
// text is valid UTF-8 and fits a close reason, never an exception (a number beyond a double's
// range is nlohmann's out_of_range, not its parse_error) and never the peer's bytes echoed.
TEST(ControlMessages, HostileValuesAreRefusedWithoutThrowing) {
  const char* const templates[] = {
      R"({"type": "hello", "protocol": @, "station_token": "t", "agent": "a"})",
      R"({"type": "hello", "protocol": 1, "station_token": @, "agent": "a"})",
      R"({"type": "hello", "protocol": 1, "station_token": "t", "agent": "a", "x": @})",
      R"({"type": @, "protocol": 1, "station_token": "t", "agent": "a"})",
      R"({"type": "welcome", "protocol": 1, "station_id": @, "station_name": "n"})",
      R"({"type": "welcome", "protocol": 1, "station_id": 1, "station_name": "n",
          "calibration": {"devices": [@]}})",
      R"({"type": "session", "session_id": @, "state": "idle"})",
      R"({"type": "link", "loop_hz": @, "rtt_p50_ms": 1, "rtt_p99_ms": 1, "loss_down": 0,
          "states_sent": 1, "states_held": 0, "devices": []})",
      R"({"type": "link", "loop_hz": 1, "rtt_p50_ms": 1, "rtt_p99_ms": 1, "loss_down": 0,
          "states_sent": @, "states_held": 0, "devices": []})",
      R"({"type": "calibration", "calibration": {"scale": @}})",
  };
  const std::function<std::string(const std::string&)> parsers[] = {
      [](const std::string& t) { return parse_hello(t).error; },
      [](const std::string& t) { return parse_welcome(t).error; },
      [](const std::string& t) { return parse_session_notice(t).error; },
      [](const std::string& t) { return parse_link_report(t).error; },
      [](const std::string& t) { return parse_calibration_notice(t).error; },
      [](const std::string& t) { return message_type(t).empty() ? "no type" : ""; },
  };
  for (const auto& value : test::hostile_values()) {
    for (const char* message : templates) {
      const std::string text = test::with_value(message, value.token);
      for (const auto& parse : parsers) {
        std::string error;
        ASSERT_NO_THROW(error = parse(text)) << value.what << " in " << text;
        EXPECT_FALSE(error.empty()) << value.what << " in " << text;
        EXPECT_TRUE(test::is_utf8(error)) << value.what << ": " << error;
        EXPECT_LE(error.size(), kMaxCloseReasonSize) << value.what;
      }
    }
  }
  // The number's error says what it is, not just "syntax".
  EXPECT_EQ(parse_hello(test::with_value(templates[0], "1e400")).error,
            "hello: not valid JSON (a number beyond the range of a double)");
  EXPECT_EQ(parse_session_notice(test::with_value(templates[6], "-1e400")).error,
            "session: not valid JSON (a number beyond the range of a double)");
}

}  // namespace
}  // namespace incise::devices
