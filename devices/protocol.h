#pragma once
// The station agent <-> server wire protocol (docs/api.md, "Station agent WebSocket").
//
// Text frames carry JSON control messages. The agent opens with hello, the server answers with
// welcome or closes with 1008 (policy) and a reason:
//   {"type": "hello", "protocol": 1, "station_token": s, "agent": s}
//   {"type": "welcome", "protocol": 1, "station_id": n, "station_name": s}
//
// Binary frames carry one message each: a fixed header, then the payload. All fields are
// little-endian whatever the host, packed without padding:
//
//   offset size  header field
//        0    2  type            MessageType
//        2    2  flags           none defined in protocol 1: must be 0
//        4    4  payload_length  bytes after the header; must equal the frame size - 20
//        8    4  sequence        per connection, 0 for the first message, +1 each, wraps at 2^32
//       12    8  timestamp_us    sample time on the sender's monotonic clock [us]; arbitrary
//                                epoch (the agent's start), so only differences are meaningful
//
//   offset size  DeviceState payload (62 bytes; offsets from the payload start)
//        0    1  device_index    u8
//        1    1  buttons         u8, bit i set = button i pressed
//        2    4  jaw             f32 in [0, 1]
//        6   24  position        3 x f64: tool tip x, y, z [m]
//       30   32  orientation     4 x f64: unit quaternion w, x, y, z (|q| within 1e-3 of 1)
//
// encode() and decode() never allocate: the agent calls them at the device rate, the server once
// per received frame. A decode error's reason() is meant to be the WebSocket close reason (1007).

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "devices/device_state.h"
#include "devices/parse_result.h"

namespace incise::devices {

inline constexpr int kProtocolVersion = 1;

enum class MessageType : uint16_t {
  DeviceState = 1,  // agent -> server
  ForceModel = 2,   // reserved: server -> agent local force model (linearised contact)
  Control = 3,      // reserved
};

inline constexpr std::size_t kHeaderSize = 20;
inline constexpr std::size_t kDeviceStatePayloadSize = 62;
inline constexpr std::size_t kDeviceStateFrameSize = kHeaderSize + kDeviceStatePayloadSize;

// Read limit for every message on the /agent socket, text or binary, in either direction.
inline constexpr std::size_t kMaxMessageSize = 4096;

// A WebSocket close reason may hold 123 bytes; ours stay within this.
inline constexpr std::size_t kMaxCloseReasonSize = 120;

// Longest strings accepted in hello and welcome [bytes]: far above real use, small enough to
// bound memory and logs.
inline constexpr std::size_t kMaxStationTokenSize = 256;
inline constexpr std::size_t kMaxNameSize = 128;  // hello "agent", welcome "station_name"

// How far |q| may stray from 1 before an orientation is rejected.
inline constexpr double kUnitQuaternionTolerance = 1e-3;

struct FrameHeader {
  MessageType type = MessageType::DeviceState;
  uint16_t flags = 0;
  uint32_t payload_length = 0;
  uint32_t sequence = 0;
  uint64_t timestamp_us = 0;
  friend bool operator==(const FrameHeader&, const FrameHeader&) = default;
};

// Writes the DeviceState frame (kDeviceStateFrameSize bytes) to the front of out.
// The state is written as given; the receiver validates it.
// Returns the number of bytes written, or 0 (and writes nothing) if out is too small.
[[nodiscard]] std::size_t encode(const DeviceState& state, uint32_t sequence, uint64_t timestamp_us,
                                 std::span<uint8_t> out);

enum class DecodeErrc {
  None,
  TooShort,           // fewer bytes than the header
  LengthMismatch,     // payload_length disagrees with the bytes that follow the header
  UnknownType,        // a type protocol 1 does not define
  UnsupportedType,    // a reserved type (ForceModel, Control) that is not accepted yet
  BadFlags,           // a flag bit set; protocol 1 defines none
  BadPayloadSize,     // the payload has the wrong size for its type
  NonFinite,          // NaN or infinity in jaw, position or orientation
  JawOutOfRange,      // jaw outside [0, 1]
  NotUnitQuaternion,  // | |q| - 1 | > kUnitQuaternionTolerance
};

struct DeviceStateMessage {
  FrameHeader header;
  DeviceState state;
};

// A decoded message, or why the frame was rejected. Holds its reason text inline so that
// decoding never allocates.
class DecodeResult {
 public:
  static DecodeResult success(const DeviceStateMessage& message);
  // reason is printf-formatted and clipped to kMaxCloseReasonSize bytes.
  static DecodeResult failure(DecodeErrc error, const char* format, ...)
      __attribute__((format(printf, 2, 3)));

  bool ok() const { return error_ == DecodeErrc::None; }
  explicit operator bool() const { return ok(); }
  DecodeErrc error() const { return error_; }
  // Empty when ok(); else e.g. `jaw 1.5 outside [0, 1]`, at most kMaxCloseReasonSize bytes.
  std::string_view reason() const { return {reason_.data(), reason_size_}; }
  // Precondition: ok().
  const DeviceStateMessage& message() const { return message_; }

 private:
  DecodeErrc error_ = DecodeErrc::None;
  DeviceStateMessage message_{};
  std::array<char, kMaxCloseReasonSize + 1> reason_{};
  std::size_t reason_size_ = 0;
};

// Parses and validates one binary frame.
DecodeResult decode(std::span<const uint8_t> frame);

// JSON control messages. Builders produce compact JSON for a text frame; parsers accept any
// key order, ignore keys they do not know (so newer peers may add information) and report the
// first problem, within kMaxCloseReasonSize bytes so that it can be the close reason.

struct Hello {
  std::string station_token;  // secret shown once when the station was created
  std::string agent;          // software and device, e.g. "incise-agent/0.1.0 (simulated)"
  friend bool operator==(const Hello&, const Hello&) = default;
};

struct Welcome {
  int64_t station_id = 0;  // > 0
  std::string station_name;
  friend bool operator==(const Welcome&, const Welcome&) = default;
};

std::string build_hello(const Hello& hello);
std::string build_welcome(const Welcome& welcome);

// Server side. A version mismatch reads `protocol 2 not supported (server speaks 1)`.
ParseResult<Hello> parse_hello(std::string_view text);
// Agent side. A version mismatch reads `protocol 2 not supported (agent speaks 1)`.
ParseResult<Welcome> parse_welcome(std::string_view text);

}  // namespace incise::devices
