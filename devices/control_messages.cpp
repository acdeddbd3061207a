// JSON control messages of the agent <-> server protocol (hello, welcome, session); see
// protocol.h.

#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>
#include <utility>

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

// Parses text as a JSON object into object; returns "" or `<what>not valid JSON ...` /
// `<what>expected a JSON object, got ...` (what ends with ": "). Catches every error the parser
// raises: syntax errors (invalid UTF-8 and lone surrogate escapes among them) and numbers beyond
// a double's range (out_of_range 406, e.g. 1e400). The error never echoes the peer's bytes.
std::string parse_object(std::string_view text, const std::string& what, json& object) {
  json parsed;
  try {
    parsed = json::parse(text);
  } catch (const json::parse_error& e) {
    return what + "not valid JSON (syntax error at byte " + std::to_string(e.byte) + ")";
  } catch (const json::out_of_range&) {
    return what + "not valid JSON (a number beyond the range of a double)";
  } catch (const json::exception&) {
    return what + "not valid JSON";
  }
  if (!parsed.is_object()) return what + "expected a JSON object, got " + parsed.type_name();
  object = std::move(parsed);
  return {};
}

// Parses a JSON object whose "type" is expected_type and whose "protocol" is ours.
// On failure returns the error (prefixed with the message name) and leaves object untouched.
std::string parse_envelope(std::string_view text, const char* expected_type, const char* speaker,
                           json& object) {
  const std::string what = expected_type;
  json parsed;
  if (auto error = parse_object(text, what + ": ", parsed); !error.empty()) return error;
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
  json message = {{"type", "welcome"},
                  {"protocol", kProtocolVersion},
                  {"station_id", welcome.station_id},
                  {"station_name", welcome.station_name}};
  if (!welcome.calibration.empty()) {
    // Only a JSON object goes out; anything else would make the whole welcome invalid.
    json calibration = json::parse(welcome.calibration, nullptr, false);
    if (calibration.is_object()) message["calibration"] = std::move(calibration);
  }
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
  if (error.empty() && object.contains("calibration")) {
    const json& calibration = object["calibration"];
    if (!calibration.is_object()) {
      error =
          std::string("welcome: \"calibration\" must be an object, got ") + calibration.type_name();
    } else {
      welcome.calibration = calibration.dump();
    }
  }
  if (!error.empty()) return ParseResult<Welcome>::failure(clip(std::move(error)));
  return ParseResult<Welcome>::success(std::move(welcome));
}

ParseResult<SessionNotice> parse_session_notice(std::string_view text) {
  using Result = ParseResult<SessionNotice>;
  const std::string what = "session: ";
  json object;
  if (auto error = parse_object(text, what, object); !error.empty()) return Result::failure(error);
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

namespace incise::devices {
namespace {

using nlohmann::json;

// Reads object[key] as a finite number in [low, high].
std::string read_number(const json& object, const char* key, double low, double high, double& out) {
  if (!object.contains(key)) return std::string("missing key \"") + key + "\"";
  const json& value = object[key];
  if (!value.is_number()) {
    return std::string("\"") + key + "\" must be a number, got " + value.type_name();
  }
  const double number = value.get<double>();
  if (!std::isfinite(number) || number < low || number > high) {
    char bounds[64];
    std::snprintf(bounds, sizeof bounds, "[%g, %g]", low, high);
    return std::string("\"") + key + "\" must be in " + bounds + ", got " + excerpt(value);
  }
  out = number;
  return {};
}

std::string read_count(const json& object, const char* key, uint64_t& out) {
  if (!object.contains(key)) return std::string("missing key \"") + key + "\"";
  const json& value = object[key];
  if (!value.is_number_unsigned() && !(value.is_number_integer() && value.get<int64_t>() >= 0)) {
    return std::string("\"") + key + "\" must be a non-negative integer, got " + excerpt(value);
  }
  out = value.get<uint64_t>();
  return {};
}

std::string read_device_report(const json& entry, DeviceLinkReport& out) {
  if (!entry.is_object()) return std::string("expected an object, got ") + entry.type_name();
  double index = 0;
  if (auto error = read_number(entry, "index", 0, kMaxStationDevices - 1, index); !error.empty())
    return error;
  if (index != std::floor(index))
    return "\"index\" must be an integer, got " + excerpt(entry["index"]);
  out.index = static_cast<int>(index);
  for (auto [key, target, high] : {std::tuple{"model_age_ms", &out.model_age_ms, 1e7},
                                   std::tuple{"force_n", &out.force_n, 1e3},
                                   std::tuple{"damping_ns_m", &out.damping_ns_m, 1e6},
                                   std::tuple{"dissipated_j", &out.dissipated_j, 1e9}}) {
    if (auto error = read_number(entry, key, 0, high, *target); !error.empty()) return error;
  }
  if (!entry.contains("fault") || !entry["fault"].is_string()) return "\"fault\" must be a string";
  out.fault = entry["fault"].get<std::string>();
  if (out.fault.size() > 64) return "\"fault\" is longer than 64 bytes";
  return {};
}

}  // namespace

std::string build_link_report(const LinkReport& report) {
  json devices = json::array();
  for (const DeviceLinkReport& d : report.devices) {
    devices.push_back({{"index", d.index},
                       {"model_age_ms", d.model_age_ms},
                       {"fault", d.fault},
                       {"force_n", d.force_n},
                       {"damping_ns_m", d.damping_ns_m},
                       {"dissipated_j", d.dissipated_j}});
  }
  const json message = {{"type", "link"},
                        {"loop_hz", report.loop_hz},
                        {"rtt_p50_ms", report.rtt_p50_ms},
                        {"rtt_p99_ms", report.rtt_p99_ms},
                        {"loss_down", report.loss_down},
                        {"states_sent", report.states_sent},
                        {"states_held", report.states_held},
                        {"devices", std::move(devices)}};
  return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

ParseResult<LinkReport> parse_link_report(std::string_view text) {
  using Result = ParseResult<LinkReport>;
  const std::string what = "link: ";
  json object;
  if (auto error = parse_object(text, what, object); !error.empty()) return Result::failure(error);
  if (message_type(text) != "link") return Result::failure(what + "\"type\" must be \"link\"");
  LinkReport report;
  for (auto [key, target, high] : {std::tuple{"loop_hz", &report.loop_hz, 1e5},
                                   std::tuple{"rtt_p50_ms", &report.rtt_p50_ms, 1e7},
                                   std::tuple{"rtt_p99_ms", &report.rtt_p99_ms, 1e7},
                                   std::tuple{"loss_down", &report.loss_down, 1.0}}) {
    if (auto error = read_number(object, key, 0, high, *target); !error.empty())
      return Result::failure(clip(what + error));
  }
  for (auto [key, target] : {std::pair{"states_sent", &report.states_sent},
                             std::pair{"states_held", &report.states_held}}) {
    if (auto error = read_count(object, key, *target); !error.empty())
      return Result::failure(clip(what + error));
  }
  if (!object.contains("devices") || !object["devices"].is_array())
    return Result::failure(what + "\"devices\" must be an array");
  const json& devices = object["devices"];
  if (devices.size() > kMaxStationDevices) {
    return Result::failure(what + "\"devices\" has " + std::to_string(devices.size()) +
                           " entries, at most " + std::to_string(kMaxStationDevices));
  }
  for (std::size_t i = 0; i < devices.size(); ++i) {
    DeviceLinkReport device;
    if (auto error = read_device_report(devices[i], device); !error.empty())
      return Result::failure(clip(what + "devices[" + std::to_string(i) + "]: " + error));
    report.devices.push_back(std::move(device));
  }
  return Result::success(std::move(report));
}

std::string build_calibration_notice(const std::string& calibration_json) {
  json message = {{"type", "calibration"}};
  json calibration = json::parse(calibration_json, nullptr, false);
  message["calibration"] = calibration.is_object() ? std::move(calibration) : json::object();
  return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

ParseResult<std::string> parse_calibration_notice(std::string_view text) {
  using Result = ParseResult<std::string>;
  const json object = json::parse(text, nullptr, false);
  if (object.is_discarded()) return Result::failure("calibration: not valid JSON");
  if (!object.is_object() || !object.contains("calibration") || !object["calibration"].is_object())
    return Result::failure("calibration: \"calibration\" must be an object");
  return Result::success(object["calibration"].dump());
}

std::string message_type(std::string_view text) {
  const json object = json::parse(text, nullptr, false);
  if (!object.is_object() || !object.contains("type") || !object["type"].is_string()) return {};
  return object["type"].get<std::string>();
}

}  // namespace incise::devices
