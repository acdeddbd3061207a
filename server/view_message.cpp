#include "server/view_message.h"

#include <algorithm>
#include <cmath>

#include "server/json_input.h"
#include "server/wire_text.h"

namespace incise::server {

namespace {

// A control message is a small flat object: 8 levels is plenty.
constexpr int kMaxDepth = 8;

// Reads the fields of one message of type `type`; the first problem wins, and error() is then
// the close reason's text (`ack needs "frame"`, `configure: "fps" must be an integer in [1, 60]`).
class Fields {
 public:
  Fields(const nlohmann::json& object, const std::string& type) : object_(object), type_(type) {}

  // A JSON number (parsed numbers are always finite: the parser refuses overflow).
  std::optional<double> number(const char* key, bool required = false) {
    const auto it = object_.find(key);
    if (!error_.empty()) return std::nullopt;
    if (it == object_.end()) {
      if (required) error_ = type_ + " needs \"" + key + "\"";
      return std::nullopt;
    }
    if (!it->is_number()) {
      error_ = type_ + ": \"" + key + "\" must be a number";
      return std::nullopt;
    }
    return it->get<double>();
  }

  // An integer within [lo, hi]: compared as a double before any conversion.
  std::optional<std::int64_t> integer(const char* key, std::int64_t lo, std::int64_t hi,
                                      bool required = false) {
    const auto v = number(key, required);
    if (!v) return std::nullopt;
    if (*v != std::floor(*v) || *v < static_cast<double>(lo) || *v > static_cast<double>(hi)) {
      error_ = type_ + ": \"" + key + "\" must be an integer in [" + std::to_string(lo) + ", " +
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
  const std::string& type_;
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
  Fields fields(object, type);
  ViewMessage m;
  if (type == "ack") {
    m.type = ViewMessage::Type::ack;
    m.frame =
        fields.integer("frame", 1, std::max<std::int64_t>(1, frames_issued), true).value_or(0);
  } else if (type == "configure") {
    m.type = ViewMessage::Type::configure;
    m.fps = fields.small_integer("fps", 1, 60);
    m.width = fields.small_integer("width", 160, 1280);
    m.height = fields.small_integer("height", 120, 960);
    if (const auto view = object.find("view"); view != object.end()) {
      if (view->is_string() && *view == "scope") {
        m.outside = false;
      } else if (view->is_string() && *view == "outside") {
        m.outside = true;
      } else {
        return fail("configure: \"view\" must be \"scope\" or \"outside\"");
      }
    }
  } else if (replay && type == "play") {
    m.type = ViewMessage::Type::play;
  } else if (replay && type == "pause") {
    m.type = ViewMessage::Type::pause;
  } else if (replay && type == "speed") {
    m.type = ViewMessage::Type::speed;
    m.value = fields.number("value", true).value_or(1);
    // The replay's range (live::ReplaySession::kMinSpeed..kMaxSpeed): refused, not clamped, so
    // that a client asking for 10x learns it did not get it.
    if (fields.error().empty() && !(m.value >= 0.25 && m.value <= 4.0)) {
      return fail("speed: \"value\" must be in [0.25, 4]");
    }
  } else if (replay && type == "seek") {
    m.type = ViewMessage::Type::seek;
    m.value = fields.number("t", true).value_or(0);
  } else {
    return fail("unknown message type \"" + clip_utf8(type, 40) + "\"");
  }
  if (!fields.error().empty()) return fail(fields.error());
  return {m, ""};
}

}  // namespace incise::server
