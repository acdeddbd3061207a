#pragma once
// A viewer's control message on the view WebSocket (docs/api.md, "View WebSocket"), read from the
// text the viewer sent and checked against what this viewer may ask. Plain function, no I/O: the
// ViewSession applies the result, or closes with the error as its reason (code 1007).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace incise::server {

struct ViewMessage {
  enum class Type { ack, configure, play, pause, speed, seek };
  Type type = Type::ack;
  std::int64_t frame = 0;  // ack: the frame acknowledged, 1..frames issued
  // configure: each within the documented limits (fps 1..60, width 160..1280, height 120..960)
  std::optional<int> fps, width, height;
  // configure: "view": "scope" (false) or "outside" (true), the picture's camera
  std::optional<bool> outside;
  double value = 0;  // speed: the factor as sent (the replay clamps it); seek: the time [s]
};

struct ViewMessageResult {
  std::optional<ViewMessage> message;
  std::string error;  // when !message: the close reason, valid UTF-8 of at most 123 bytes
};

// `frames_issued`: the newest frame number sent to this viewer (an ack of a later one would switch
// off its flow control); `replay`: whether play, pause, speed and seek are allowed. Never throws
// on any input.
ViewMessageResult parse_view_message(std::string_view text, std::int64_t frames_issued,
                                     bool replay);

}  // namespace incise::server
