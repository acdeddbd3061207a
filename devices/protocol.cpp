// Binary framing of the agent <-> server protocol; the layout is documented in protocol.h.

#include "devices/protocol.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "devices/little_endian.h"

namespace incise::devices {
namespace {

// Header field offsets.
constexpr std::size_t kTypeAt = 0;
constexpr std::size_t kFlagsAt = 2;
constexpr std::size_t kPayloadLengthAt = 4;
constexpr std::size_t kSequenceAt = 8;
constexpr std::size_t kTimestampAt = 12;

// DeviceState payload field offsets, from the payload start.
constexpr std::size_t kDeviceIndexAt = 0;
constexpr std::size_t kButtonsAt = 1;
constexpr std::size_t kJawAt = 2;
constexpr std::size_t kPositionAt = 6;
constexpr std::size_t kOrientationAt = 30;
static_assert(kOrientationAt + 4 * 8 == kDeviceStatePayloadSize);

void store_header(const FrameHeader& header, uint8_t* out) {
  store_le(static_cast<uint16_t>(header.type), out + kTypeAt);
  store_le(header.flags, out + kFlagsAt);
  store_le(header.payload_length, out + kPayloadLengthAt);
  store_le(header.sequence, out + kSequenceAt);
  store_le(header.timestamp_us, out + kTimestampAt);
}

// The first non-finite value of the state, named as in the docs, or nullptr.
const char* first_non_finite(const DeviceState& s, double& value) {
  const std::pair<const char*, double> fields[] = {
      {"jaw", s.jaw},
      {"position.x", s.position.x},
      {"position.y", s.position.y},
      {"position.z", s.position.z},
      {"orientation.w", s.orientation.w},
      {"orientation.x", s.orientation.x},
      {"orientation.y", s.orientation.y},
      {"orientation.z", s.orientation.z},
  };
  for (const auto& [name, v] : fields) {
    if (!std::isfinite(v)) {
      value = v;
      return name;
    }
  }
  return nullptr;
}

DecodeResult decode_device_state(const FrameHeader& header, const uint8_t* payload) {
  if (header.payload_length != kDeviceStatePayloadSize) {
    return DecodeResult::failure(DecodeErrc::BadPayloadSize,
                                 "DeviceState payload is %u bytes, expected %zu",
                                 header.payload_length, kDeviceStatePayloadSize);
  }
  DeviceState s;
  s.device_index = payload[kDeviceIndexAt];
  s.buttons = payload[kButtonsAt];
  s.jaw = load_le_f32(payload + kJawAt);
  s.position = {load_le_f64(payload + kPositionAt), load_le_f64(payload + kPositionAt + 8),
                load_le_f64(payload + kPositionAt + 16)};
  s.orientation = {load_le_f64(payload + kOrientationAt), load_le_f64(payload + kOrientationAt + 8),
                   load_le_f64(payload + kOrientationAt + 16),
                   load_le_f64(payload + kOrientationAt + 24)};

  double bad = 0.0;
  if (const char* name = first_non_finite(s, bad)) {
    return DecodeResult::failure(DecodeErrc::NonFinite, "%s is not finite (%g)", name, bad);
  }
  if (!(s.jaw >= 0.0f && s.jaw <= 1.0f)) {
    return DecodeResult::failure(DecodeErrc::JawOutOfRange, "jaw %g outside [0, 1]",
                                 static_cast<double>(s.jaw));
  }
  const Quat& q = s.orientation;
  const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!(std::abs(norm - 1.0) <= kUnitQuaternionTolerance)) {
    return DecodeResult::failure(DecodeErrc::NotUnitQuaternion,
                                 "orientation is not a unit quaternion: |q| = %.6g (tolerance %g)",
                                 norm, kUnitQuaternionTolerance);
  }
  return DecodeResult::success({header, s});
}

}  // namespace

std::size_t encode(const DeviceState& state, uint32_t sequence, uint64_t timestamp_us,
                   std::span<uint8_t> out) {
  if (out.size() < kDeviceStateFrameSize) return 0;
  uint8_t* frame = out.data();
  store_header({MessageType::DeviceState, 0, kDeviceStatePayloadSize, sequence, timestamp_us},
               frame);
  uint8_t* payload = frame + kHeaderSize;
  payload[kDeviceIndexAt] = state.device_index;
  payload[kButtonsAt] = state.buttons;
  store_le_f32(state.jaw, payload + kJawAt);
  store_le_f64(state.position.x, payload + kPositionAt);
  store_le_f64(state.position.y, payload + kPositionAt + 8);
  store_le_f64(state.position.z, payload + kPositionAt + 16);
  store_le_f64(state.orientation.w, payload + kOrientationAt);
  store_le_f64(state.orientation.x, payload + kOrientationAt + 8);
  store_le_f64(state.orientation.y, payload + kOrientationAt + 16);
  store_le_f64(state.orientation.z, payload + kOrientationAt + 24);
  return kDeviceStateFrameSize;
}

DecodeResult decode(std::span<const uint8_t> frame) {
  if (frame.size() < kHeaderSize) {
    return DecodeResult::failure(DecodeErrc::TooShort, "frame too short: %zu bytes, header is %zu",
                                 frame.size(), kHeaderSize);
  }
  const uint8_t* in = frame.data();
  const uint16_t type = load_le<uint16_t>(in + kTypeAt);
  FrameHeader header;
  header.type = static_cast<MessageType>(type);
  header.flags = load_le<uint16_t>(in + kFlagsAt);
  header.payload_length = load_le<uint32_t>(in + kPayloadLengthAt);
  header.sequence = load_le<uint32_t>(in + kSequenceAt);
  header.timestamp_us = load_le<uint64_t>(in + kTimestampAt);

  const std::size_t carried = frame.size() - kHeaderSize;
  if (header.payload_length != carried) {
    return DecodeResult::failure(DecodeErrc::LengthMismatch,
                                 "length mismatch: header says %u payload bytes, frame has %zu",
                                 header.payload_length, carried);
  }
  switch (header.type) {
    case MessageType::DeviceState:
      break;
    case MessageType::ForceModel:
    case MessageType::Control:
      return DecodeResult::failure(DecodeErrc::UnsupportedType,
                                   "message type %u (%s) is reserved, not accepted in protocol %d",
                                   type, type == 2 ? "ForceModel" : "Control", kProtocolVersion);
    default:
      return DecodeResult::failure(DecodeErrc::UnknownType, "unknown message type %u", type);
  }
  if (header.flags != 0) {
    return DecodeResult::failure(DecodeErrc::BadFlags, "flags 0x%04x set, protocol %d defines none",
                                 header.flags, kProtocolVersion);
  }
  return decode_device_state(header, in + kHeaderSize);
}

DecodeResult DecodeResult::success(const DeviceStateMessage& message) {
  DecodeResult result;
  result.message_ = message;
  return result;
}

DecodeResult DecodeResult::failure(DecodeErrc error, const char* format, ...) {
  DecodeResult result;
  result.error_ = error;
  va_list args;
  va_start(args, format);
  const int written = std::vsnprintf(result.reason_.data(), result.reason_.size(), format, args);
  va_end(args);
  // vsnprintf reports the untruncated length; the buffer holds at most size - 1 characters.
  result.reason_size_ = std::min<std::size_t>(written < 0 ? 0 : written, kMaxCloseReasonSize);
  return result;
}

}  // namespace incise::devices
