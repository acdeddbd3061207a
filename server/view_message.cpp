#include "server/view_message.h"

#include <algorithm>
#include <cmath>

#include "server/json_input.h"
#include "server/wire_text.h"

namespace incise::server {

namespace {

// A control message is a small flat object: 8 levels is plenty.
constexpr int kMaxDepth = 8;

// Reads the optional fields of one message; the first problem wins and ends the reading.
class Fields {
 public:
  explicit Fields(const nlohmann::json& object) : object_(object) {}

  std::optional<double> number(const char* key) {
    const auto it = object_.find(key);
    if (it == object_.end() || !error_.empty()) return std::nullopt;
    // Parsed JSON numbers are finite (overflow is refused by the parser); checked all the same.
    if (!it->is_number() || !std::isfinite(it->get<double>())) {
      error_ = std::string("\"") + key + "\" must be a number";
      return std::nullopt;
    }
    return it->get<double>();
  }

  // An integer within [lo, hi]: compared as a double before any conversion.
  std::optional<std::int64_t> integer(const char* key, std::int64_t lo, std::int64_t hi) {
    const auto v = number(key);
    if (!v) return std::nullopt;
    if (*v != std::floor(*v) || *v < static_cast<double>(lo) || *v > static_cast<double>(hi)) {
      error_ = std::string("\"") + key + "\" must be an integer in [" + std::to_string(lo) + ", " +
               std::to_string(hi) + "]";
      return std::nullopt;
    }
    return static_cast<std::int64_t>(*v);
  }

  std::optional<int> small_integer(const char* key, int lo, int hi) {
    const auto v = integer(key, lo, hi);
    return v ? std::optional<int>(static_cast<int>(*v)) : std::nullopt;
  }

  const std::string& error() const { return error_; }

 private:
  const nlohmann::json& object_;
  std::string error_;
};

ViewMessageResult fail(std::string reason) {
  return {std::nullopt, close_reason_text(reason)};
}

}  // namespace

ViewMessageResult parse_view_message(std::string_view text, std::int64_t frames_issued,
                                     bool replay) {
  const auto input = parse_json_input(text, kMaxDepth);
  if (!input) return fail("malformed JSON: " + input.message);
  const auto& object = input.value;
  const auto type_it = object.is_object() ? object.find("type") : object.end();
  if (!object.is_object() || type_it == object.end() || !type_it->is_string()) {
    return fail("a message must be an object with a string \"type\"");
  }
  const auto& type = type_it->get_ref<const std::string&>();
  Fields fields(object);
  ViewMessage m;
  std::string missing;
  if (type == "ack") {
    m.type = ViewMessage::Type::ack;
    const auto frame = fields.integer("frame", 1, std::max<std::int64_t>(1, frames_issued));
    if (frame) m.frame = *frame;
    if (!frame && fields.error().empty()) missing = "ack needs \"frame\"";
  } else if (type == "configure") {
    m.type = ViewMessage::Type::configure;
    m.fps = fields.small_integer("fps", 1, 60);
    m.width = fields.small_integer("width", 160, 1280);
    m.height = fields.small_integer("height", 120, 960);
  } else if (replay && type == "play") {
    m.type = ViewMessage::Type::play;
  } else if (replay && type == "pause") {
    m.type = ViewMessage::Type::pause;
  } else if (replay && (type == "speed" || type == "seek")) {
    const bool speed = type == "speed";
    m.type = speed ? ViewMessage::Type::speed : ViewMessage::Type::seek;
    const auto value = fields.number(speed ? "value" : "t");
    if (value) m.value = *value;
    if (!value && fields.error().empty())
      missing = type + (speed ? " needs \"value\"" : " needs \"t\"");
  } else {
    return fail("unknown message type \"" + clip_utf8(type, 40) + "\"");
  }
  if (!fields.error().empty()) return fail(type + ": " + fields.error());
  if (!missing.empty()) return fail(missing);
  return {m, ""};
}

}  // namespace incise::server
