#pragma once
// The station agent <-> server wire protocol (docs/api.md, "Station agent WebSocket").
//
// Text frames carry JSON control messages. The agent opens with hello, the server answers with
// welcome or closes with 1008 (policy) and a reason:
//   {"type": "hello", "protocol": 1, "station_token": s, "agent": s}
//   {"type": "welcome", "protocol": 1, "station_id": n, "station_name": s, "calibration": {...}}
// ("calibration" optional: the station's devices/kinematics.h StationCalibration)
// After welcome the server tells the agent whenever the station's live session changes state:
//   {"type": "session", "session_id": n, "state": "running" | "paused" | "idle"}
// (session_id >= 1; 0 only with "idle", for a station that has no session).
//
// Message directions after welcome: agent -> server DeviceState frames at the agent's send rate
// (250..1000 Hz); server -> agent ForceModel frames (typically one per received state, each
// echoing that state's timestamp) and session notices. Whoever receives a malformed message
// closes with 1007 and the decode error's reason.
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
//   offset size  DeviceState payload (62 bytes; offsets from the payload start), agent -> server
//        0    1  device_index    u8, 0 or 1 (a station's two hands)
//        1    1  buttons         u8, bit i set = button i pressed
//        2    4  jaw             f32 in [0, 1]
//        6   24  position        3 x f64: tool tip x, y, z [m]
//       30   32  orientation     4 x f64: unit quaternion w, x, y, z (|q| within 1e-3 of 1)
//
//   offset size  ForceModel payload (137 bytes), server -> agent
//        0    1  device_index        u8
//        1   24  reference_position  3 x f64: tool tip x, y, z the model linearises about [m]
//       25   24  force               3 x f64: force on the hand at reference_position [N],
//                                    |force| <= kMaxModelForce (100 N)
//       49   72  stiffness           9 x f64: K row-major, K[3 * row + column] [N/m],
//                                    each |K_ij| <= kMaxModelStiffness (1e5 N/m)
//      121    8  state_timestamp_us  u64: timestamp_us of the agent's DeviceState frame the model
//                                    answers (its header field, echoed for the round trip)
//      129    8  sim_time_s          f64: the server's simulation time of the model [s]
//
// The agent renders force(x) = force - K (x - reference_position) at every haptic tick, so the
// 1 kHz loop never waits for the network. The header timestamp_us of a ForceModel is the server's
// own clock (its epoch is arbitrary too); the round trip uses state_timestamp_us, which is ours.
//
// encode() and the decoders never allocate: the agent calls them at the device rate, the server
// once per received frame. A decode error's reason() is meant to be the WebSocket close reason
// (1007).

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "devices/device_state.h"
#include "devices/parse_result.h"

namespace incise::devices {

inline constexpr int kProtocolVersion = 1;

enum class MessageType : uint16_t {
  DeviceState = 1,  // agent -> server
  ForceModel = 2,   // server -> agent: local force model (linearised contact)
  Control = 3,      // reserved
};

inline constexpr std::size_t kHeaderSize = 20;
inline constexpr std::size_t kDeviceStatePayloadSize = 62;
inline constexpr std::size_t kDeviceStateFrameSize = kHeaderSize + kDeviceStatePayloadSize;
inline constexpr std::size_t kForceModelPayloadSize = 137;
inline constexpr std::size_t kForceModelFrameSize = kHeaderSize + kForceModelPayloadSize;

// Bounds of a ForceModel. Far above what a desktop haptic device renders (a few N, stiffness of
// a few kN/m), so only corrupt or runaway models are refused; the device clamps to its own limits.
inline constexpr double kMaxModelForce = 100.0;      // |force| [N]
inline constexpr double kMaxModelStiffness = 1.0e5;  // |K_ij| [N/m]

// Read limit for every message on the /agent socket, text or binary, in either direction.
inline constexpr std::size_t kMaxMessageSize = 4096;

// A WebSocket close reason may hold 123 bytes; ours stay within this.
inline constexpr std::size_t kMaxCloseReasonSize = 120;

// Longest strings accepted in hello and welcome [bytes]: far above real use, small enough to
// bound memory and logs.
inline constexpr std::size_t kMaxStationTokenSize = 256;
inline constexpr std::size_t kMaxNameSize = 128;  // hello "agent", welcome "station_name"
// A station has up to two devices (two hands): device_index 0 and 1.
inline constexpr std::size_t kMaxStationDevices = 2;

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

// The local force model: a linearisation of the tool contact the agent evaluates every ms:
//   force(x) = force - K (x - reference_position),  K = stiffness (row-major 3x3, N/m).
struct ForceModel {
  uint8_t device_index = 0;
  Vec3 reference_position;            // tool tip the model linearises about [m], station frame
  Vec3 force;                         // force on the hand at reference_position [N]
  std::array<double, 9> stiffness{};  // row-major K [N/m]
  uint64_t state_timestamp_us = 0;    // timestamp_us of the agent DeviceState this answers
  double sim_time_s = 0.0;            // server simulation time of the model
  friend bool operator==(const ForceModel&, const ForceModel&) = default;
};

// Writes the ForceModel frame (kForceModelFrameSize bytes) to the front of out; as for
// DeviceState, the model is written as given, returns the bytes written or 0 if out is too small.
[[nodiscard]] std::size_t encode(const ForceModel& model, uint32_t sequence, uint64_t timestamp_us,
                                 std::span<uint8_t> out);

enum class DecodeErrc {
  None,
  TooShort,              // fewer bytes than the header
  LengthMismatch,        // payload_length disagrees with the bytes that follow the header
  UnknownType,           // a type protocol 1 does not define
  UnsupportedType,       // a type this side does not accept: the other direction's (DeviceState
                         // at the agent, ForceModel at the server) or a reserved one (Control)
  BadFlags,              // a flag bit set; protocol 1 defines none
  BadPayloadSize,        // the payload has the wrong size for its type
  NonFinite,             // NaN or infinity in a floating-point field
  JawOutOfRange,         // jaw outside [0, 1]
  NotUnitQuaternion,     // | |q| - 1 | > kUnitQuaternionTolerance
  ForceOutOfRange,       // ForceModel |force| > kMaxModelForce
  StiffnessOutOfRange,   // ForceModel |K_ij| > kMaxModelStiffness
  DeviceIndexOutOfRange  // device_index >= kMaxStationDevices
};

struct DeviceStateMessage {
  FrameHeader header;
  DeviceState state;
};

struct ForceModelMessage {
  FrameHeader header;
  ForceModel model;
};

// A decoded message, or why the frame was rejected. Holds its reason text inline so that
// decoding never allocates.
template <typename Message>
class BasicDecodeResult {
 public:
  static BasicDecodeResult success(const Message& message);
  // reason is printf-formatted and clipped to kMaxCloseReasonSize bytes.
  static BasicDecodeResult failure(DecodeErrc error, const char* format, ...)
      __attribute__((format(printf, 2, 3)));

  bool ok() const { return error_ == DecodeErrc::None; }
  explicit operator bool() const { return ok(); }
  DecodeErrc error() const { return error_; }
  // Empty when ok(); else e.g. `jaw 1.5 outside [0, 1]`, at most kMaxCloseReasonSize bytes.
  std::string_view reason() const { return {reason_.data(), reason_size_}; }
  // Precondition: ok().
  const Message& message() const { return message_; }

 private:
  DecodeErrc error_ = DecodeErrc::None;
  Message message_{};
  std::array<char, kMaxCloseReasonSize + 1> reason_{};
  std::size_t reason_size_ = 0;
};

using DecodeResult = BasicDecodeResult<DeviceStateMessage>;
using ForceModelDecodeResult = BasicDecodeResult<ForceModelMessage>;
extern template class BasicDecodeResult<DeviceStateMessage>;
extern template class BasicDecodeResult<ForceModelMessage>;

// Server side: parses and validates one binary frame from an agent (a DeviceState).
DecodeResult decode(std::span<const uint8_t> frame);

// Agent side: parses and validates one binary frame from the server (a ForceModel).
ForceModelDecodeResult decode_force_model(std::span<const uint8_t> frame);

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
  // The station's calibration (kinematics.h StationCalibration) as JSON object text; optional,
  // "" = the default. The agent validates it with parse_station_calibration.
  std::string calibration;
  friend bool operator==(const Welcome&, const Welcome&) = default;
};

// The state of the station's live session, server -> agent after welcome.
struct SessionNotice {
  int64_t session_id = 0;  // >= 1; 0 only with state "idle" (no session)
  std::string state;       // "running", "paused" or "idle"
  friend bool operator==(const SessionNotice&, const SessionNotice&) = default;
};

// The link as the agent sees it, agent -> server about once a second (text frame):
//   {"type": "link", "loop_hz": x, "rtt_p50_ms": x, "rtt_p99_ms": x, "loss_down": x, "states_sent":
//   n,
//    "states_held": n, "devices": [{"index": i, "model_age_ms": x, "fault": s, "force_n": x,
//    "damping_ns_m": x, "dissipated_j": x}, ...]}
// Round trips and loss are over the window since the previous report; loss_down is the share of
// the server's force models that never arrived (gaps in their sequence numbers); states_held
// counts the states the deadband held back. The server shows it in the session metrics.
struct DeviceLinkReport {
  int index = 0;
  double model_age_ms = 0;  // age of the model rendered (since the state it answers)
  std::string fault;        // the watchdog's reason the force is off, "none" if rendering
  double force_n = 0;       // |force| commanded
  double damping_ns_m = 0;  // damping the passivity guard injects
  double dissipated_j = 0;  // energy the passivity guard has removed since the agent started
  friend bool operator==(const DeviceLinkReport&, const DeviceLinkReport&) = default;
};
struct LinkReport {
  double loop_hz = 0;  // haptic loop ticks per second over the window
  double rtt_p50_ms = 0;
  double rtt_p99_ms = 0;
  double loss_down = 0;  // in [0, 1]
  uint64_t states_sent = 0;
  uint64_t states_held = 0;
  std::vector<DeviceLinkReport> devices;  // at most 2
  friend bool operator==(const LinkReport&, const LinkReport&) = default;
};

std::string build_hello(const Hello& hello);
std::string build_link_report(const LinkReport& report);
std::string build_welcome(const Welcome& welcome);
std::string build_session_notice(const SessionNotice& notice);

// The station's calibration changed while its agent is connected, server -> agent:
//   {"type": "calibration", "calibration": {...}}
std::string build_calibration_notice(const std::string& calibration_json);
// Agent side: the calibration object's text.
ParseResult<std::string> parse_calibration_notice(std::string_view text);

// Server side. A version mismatch reads `protocol 2 not supported (server speaks 1)`.
ParseResult<Hello> parse_hello(std::string_view text);
// Agent side. A version mismatch reads `protocol 2 not supported (agent speaks 1)`.
ParseResult<Welcome> parse_welcome(std::string_view text);
// Server side. Errors read e.g. `link: "loss_down" must be in [0, 1], got 2`.
ParseResult<LinkReport> parse_link_report(std::string_view text);
// The "type" of a text message, or "" if it is not a JSON object with a string "type".
std::string message_type(std::string_view text);

// Agent side. Errors read e.g. `session: "state" is "done", expected running, paused or idle`.
ParseResult<SessionNotice> parse_session_notice(std::string_view text);

}  // namespace incise::devices
