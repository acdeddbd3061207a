// JSON control messages of the agent <-> server protocol (hello, welcome, session); see
// protocol.h.

#include <limits>

#include <nlohmann/json.hpp>

#include "devices/protocol.h"

namespace incise::devices {
namespace {

using nlohmann::json;

// Peers may send anything; error texts must still fit a close reason.
std::string clip(std::string text) {
  if (text.size() <= kMaxCloseReasonSize) return text;
  std::size_t end = kMaxCloseReasonSize;
  // Do not cut a UTF-8 sequence in half: back up over continuation bytes (10xxxxxx).
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80)
    --end;
  text.resize(end);
  return text;
}

// A short, printable excerpt of a peer's value for an error message.
std::string excerpt(const json& value) {
  std::string text = value.dump(-1, ' ', true, json::error_handler_t::replace);
  constexpr std::size_t kMax = 24;
  if (text.size() > kMax) text = text.substr(0, kMax) + "...";
  return text;
}

// Parses a JSON object whose "type" is expected_type and whose "protocol" is ours.
// On failure returns the error (prefixed with the message name) and leaves object untouched.
std::string parse_envelope(std::string_view text, const char* expected_type, const char* speaker,
                           json& object) {
  const std::string what = expected_type;
  json parsed;
  try {
    parsed = json::parse(text);
  } catch (const json::parse_error& e) {
    return what + ": not valid JSON (syntax error at byte " + std::to_string(e.byte) + ")";
  }
  if (!parsed.is_object()) {
    return what + ": expected a JSON object, got " + parsed.type_name();
  }
  for (const char* key : {"type", "protocol"}) {
    if (!parsed.contains(key)) return what + ": missing key \"" + key + "\"";
  }
  const json& type = parsed["type"];
  if (!type.is_string()) return what + ": \"type\" must be a string, got " + type.type_name();
  if (type.get_ref<const std::string&>() != expected_type) {
    return what + ": \"type\" is " + excerpt(type) + ", expected \"" + expected_type + "\"";
  }
  const json& protocol = parsed["protocol"];
  if (!protocol.is_number_integer()) {
    return what + ": \"protocol\" must be an integer, got " + protocol.type_name();
  }
  if (protocol != kProtocolVersion) {
    return "protocol " + protocol.dump() + " not supported (" + speaker + " speaks " +
           std::to_string(kProtocolVersion) + ")";
  }
  object = std::move(parsed);
  return {};
}

// Reads object[key] as a string of 1..max_size bytes into out.
std::string read_string(const json& object, const char* what, const char* key, std::size_t max_size,
                        std::string& out) {
  const std::string where = std::string(what) + ": ";
  if (!object.contains(key)) return where + "missing key \"" + key + "\"";
  const json& value = object[key];
  if (!value.is_string()) {
    return where + "\"" + key + "\" must be a string, got " + value.type_name();
  }
  const auto& text = value.get_ref<const std::string&>();
  if (text.empty()) return where + "\"" + key + "\" is empty";
  if (text.size() > max_size) {
    return where + "\"" + key + "\" is longer than " + std::to_string(max_size) + " bytes";
  }
  out = text;
  return {};
}

// Ids are SQLite rowids: 1 .. 2^63 - 1.
bool is_positive_int64(const json& value) {
  if (value.is_number_unsigned()) {
    const auto id = value.get<uint64_t>();
    return id >= 1 && id <= static_cast<uint64_t>(std::numeric_limits<int64_t>::max());
  }
  return value.is_number_integer() && value.get<int64_t>() >= 1;
}

}  // namespace

std::string build_session_notice(const SessionNotice& notice) {
  const json message = {
      {"type", "session"}, {"session_id", notice.session_id}, {"state", notice.state}};
  return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string build_hello(const Hello& hello) {
  const json message = {{"type", "hello"},
                        {"protocol", kProtocolVersion},
                        {"station_token", hello.station_token},
                        {"agent", hello.agent}};
  return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string build_welcome(const Welcome& welcome) {
  const json message = {{"type", "welcome"},
                        {"protocol", kProtocolVersion},
                        {"station_id", welcome.station_id},
                        {"station_name", welcome.station_name}};
  return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

ParseResult<Hello> parse_hello(std::string_view text) {
  json object;
  Hello hello;
  std::string error = parse_envelope(text, "hello", "server", object);
  if (error.empty()) {
    error =
        read_string(object, "hello", "station_token", kMaxStationTokenSize, hello.station_token);
  }
  if (error.empty()) error = read_string(object, "hello", "agent", kMaxNameSize, hello.agent);
  if (!error.empty()) return ParseResult<Hello>::failure(clip(std::move(error)));
  return ParseResult<Hello>::success(std::move(hello));
}

ParseResult<Welcome> parse_welcome(std::string_view text) {
  json object;
  Welcome welcome;
  std::string error = parse_envelope(text, "welcome", "agent", object);
  if (error.empty()) {
    if (!object.contains("station_id")) {
      error = "welcome: missing key \"station_id\"";
    } else if (const json& id = object["station_id"]; !is_positive_int64(id)) {
      error = std::string("welcome: \"station_id\" must be a positive integer, got ") +
              (id.is_number_integer() ? excerpt(id) : id.type_name());
    } else {
      welcome.station_id = id.get<int64_t>();
    }
  }
  if (error.empty()) {
    error = read_string(object, "welcome", "station_name", kMaxNameSize, welcome.station_name);
  }
  if (!error.empty()) return ParseResult<Welcome>::failure(clip(std::move(error)));
  return ParseResult<Welcome>::success(std::move(welcome));
}

ParseResult<SessionNotice> parse_session_notice(std::string_view text) {
  using Result = ParseResult<SessionNotice>;
  const std::string what = "session: ";
  json object;
  try {
    object = json::parse(text);
  } catch (const json::parse_error& e) {
    return Result::failure("session: not valid JSON (syntax error at byte " +
                           std::to_string(e.byte) + ")");
  }
  if (!object.is_object()) {
    return Result::failure(what + "expected a JSON object, got " + object.type_name());
  }
  for (const char* key : {"type", "session_id", "state"}) {
    if (!object.contains(key)) return Result::failure(what + "missing key \"" + key + "\"");
  }
  const json& type = object["type"];
  if (!type.is_string()) {
    return Result::failure(what + "\"type\" must be a string, got " + type.type_name());
  }
  if (type.get_ref<const std::string&>() != "session") {
    return Result::failure(clip(what + "\"type\" is " + excerpt(type) + ", expected \"session\""));
  }
  const json& state = object["state"];
  if (!state.is_string()) {
    return Result::failure(what + "\"state\" must be a string, got " + state.type_name());
  }
  SessionNotice notice;
  notice.state = state.get<std::string>();
  if (notice.state != "running" && notice.state != "paused" && notice.state != "idle") {
    return Result::failure(
        clip(what + "\"state\" is " + excerpt(state) + ", expected running, paused or idle"));
  }
  const json& id = object["session_id"];
  const bool none = id.is_number_integer() && id.get<int64_t>() == 0;
  if (none && notice.state != "idle") {
    return Result::failure(what + "\"session_id\" 0 (no session) needs state idle, got " +
                           notice.state);
  }
  if (!none && !is_positive_int64(id)) {
    return Result::failure(what + "\"session_id\" must be a positive integer, got " +
                           (id.is_number_integer() ? excerpt(id) : id.type_name()));
  }
  notice.session_id = none ? 0 : id.get<int64_t>();
  return Result::success(std::move(notice));
}

}  // namespace incise::devices
