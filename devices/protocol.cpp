// Binary framing of the agent <-> server protocol; the layout is documented in protocol.h.

#include "devices/protocol.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <optional>
#include <utility>

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

// ForceModel payload field offsets, from the payload start.
constexpr std::size_t kModelDeviceIndexAt = 0;
constexpr std::size_t kReferenceAt = 1;
constexpr std::size_t kForceAt = 25;
constexpr std::size_t kStiffnessAt = 49;
constexpr std::size_t kStateTimestampAt = 121;
constexpr std::size_t kSimTimeAt = 129;
static_assert(kSimTimeAt + 8 == kForceModelPayloadSize);

void store_header(const FrameHeader& header, uint8_t* out) {
  store_le(static_cast<uint16_t>(header.type), out + kTypeAt);
  store_le(header.flags, out + kFlagsAt);
  store_le(header.payload_length, out + kPayloadLengthAt);
  store_le(header.sequence, out + kSequenceAt);
  store_le(header.timestamp_us, out + kTimestampAt);
}

void store_vec3(const Vec3& v, uint8_t* out) {
  store_le_f64(v.x, out);
  store_le_f64(v.y, out + 8);
  store_le_f64(v.z, out + 16);
}

Vec3 load_vec3(const uint8_t* in) {
  return {load_le_f64(in), load_le_f64(in + 8), load_le_f64(in + 16)};
}

const char* type_name(uint16_t type) {
  switch (static_cast<MessageType>(type)) {
    case MessageType::DeviceState:
      return "DeviceState";
    case MessageType::ForceModel:
      return "ForceModel";
    case MessageType::Control:
      return "Control";
  }
  return "unknown";
}

// Checks what every frame shares: size, length field, type (expected is the one type this side
// accepts, receiver names this side for the error), flags. On success fills header and returns
// nullopt; else the failure.
template <typename Result>
std::optional<Result> check_header(std::span<const uint8_t> frame, MessageType expected,
                                   const char* receiver, FrameHeader& header) {
  if (frame.size() < kHeaderSize) {
    return Result::failure(DecodeErrc::TooShort, "frame too short: %zu bytes, header is %zu",
                           frame.size(), kHeaderSize);
  }
  const uint8_t* in = frame.data();
  const uint16_t type = load_le<uint16_t>(in + kTypeAt);
  header.type = static_cast<MessageType>(type);
  header.flags = load_le<uint16_t>(in + kFlagsAt);
  header.payload_length = load_le<uint32_t>(in + kPayloadLengthAt);
  header.sequence = load_le<uint32_t>(in + kSequenceAt);
  header.timestamp_us = load_le<uint64_t>(in + kTimestampAt);

  const std::size_t carried = frame.size() - kHeaderSize;
  if (header.payload_length != carried) {
    return Result::failure(DecodeErrc::LengthMismatch,
                           "length mismatch: header says %u payload bytes, frame has %zu",
                           header.payload_length, carried);
  }
  switch (header.type) {
    case MessageType::Control:
      return Result::failure(DecodeErrc::UnsupportedType,
                             "message type %u (Control) is reserved, not accepted in protocol %d",
                             type, kProtocolVersion);
    case MessageType::DeviceState:
    case MessageType::ForceModel:
      if (header.type == expected) break;
      return Result::failure(
          DecodeErrc::UnsupportedType, "message type %u (%s) goes %s, not accepted by the %s", type,
          type_name(type),
          header.type == MessageType::DeviceState ? "agent -> server" : "server -> agent",
          receiver);
    default:
      return Result::failure(DecodeErrc::UnknownType, "unknown message type %u", type);
  }
  if (header.flags != 0) {
    return Result::failure(DecodeErrc::BadFlags, "flags 0x%04x set, protocol %d defines none",
                           header.flags, kProtocolVersion);
  }
  return std::nullopt;
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
  if (s.device_index >= kMaxStationDevices) {
    return DecodeResult::failure(DecodeErrc::DeviceIndexOutOfRange,
                                 "device_index %u, a station has devices 0 and 1",
                                 static_cast<unsigned>(s.device_index));
  }
  s.buttons = payload[kButtonsAt];
  s.jaw = load_le_f32(payload + kJawAt);
  s.position = load_vec3(payload + kPositionAt);
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

// The first non-finite value of the model, named as in the docs ("stiffness[4]"), or nullptr.
// name holds the text of an indexed name.
const char* first_non_finite(const ForceModel& m, double& value, std::array<char, 16>& name) {
  const std::pair<const char*, double> vectors[] = {
      {"reference_position.x", m.reference_position.x},
      {"reference_position.y", m.reference_position.y},
      {"reference_position.z", m.reference_position.z},
      {"force.x", m.force.x},
      {"force.y", m.force.y},
      {"force.z", m.force.z},
      {"sim_time_s", m.sim_time_s},
  };
  for (const auto& [field, v] : vectors) {
    if (!std::isfinite(v)) {
      value = v;
      return field;
    }
  }
  for (std::size_t i = 0; i < m.stiffness.size(); ++i) {
    if (!std::isfinite(m.stiffness[i])) {
      value = m.stiffness[i];
      std::snprintf(name.data(), name.size(), "stiffness[%zu]", i);
      return name.data();
    }
  }
  return nullptr;
}

ForceModelDecodeResult decode_model_payload(const FrameHeader& header, const uint8_t* payload) {
  using Result = ForceModelDecodeResult;
  if (header.payload_length != kForceModelPayloadSize) {
    return Result::failure(DecodeErrc::BadPayloadSize,
                           "ForceModel payload is %u bytes, expected %zu", header.payload_length,
                           kForceModelPayloadSize);
  }
  ForceModel m;
  m.device_index = payload[kModelDeviceIndexAt];
  if (m.device_index >= kMaxStationDevices) {
    return Result::failure(DecodeErrc::DeviceIndexOutOfRange,
                           "device_index %u, a station has devices 0 and 1",
                           static_cast<unsigned>(m.device_index));
  }
  m.reference_position = load_vec3(payload + kReferenceAt);
  m.force = load_vec3(payload + kForceAt);
  for (std::size_t i = 0; i < m.stiffness.size(); ++i) {
    m.stiffness[i] = load_le_f64(payload + kStiffnessAt + 8 * i);
  }
  m.state_timestamp_us = load_le<uint64_t>(payload + kStateTimestampAt);
  m.sim_time_s = load_le_f64(payload + kSimTimeAt);

  double bad = 0.0;
  std::array<char, 16> name_buffer{};
  if (const char* name = first_non_finite(m, bad, name_buffer)) {
    return Result::failure(DecodeErrc::NonFinite, "%s is not finite (%g)", name, bad);
  }
  const Vec3& f = m.force;
  const double magnitude = std::sqrt(f.x * f.x + f.y * f.y + f.z * f.z);
  if (!(magnitude <= kMaxModelForce)) {
    return Result::failure(DecodeErrc::ForceOutOfRange, "|force| %g N exceeds %g N", magnitude,
                           kMaxModelForce);
  }
  for (std::size_t i = 0; i < m.stiffness.size(); ++i) {
    if (!(std::abs(m.stiffness[i]) <= kMaxModelStiffness)) {
      return Result::failure(DecodeErrc::StiffnessOutOfRange,
                             "stiffness[%zu] %g N/m outside [-%g, %g]", i, m.stiffness[i],
                             kMaxModelStiffness, kMaxModelStiffness);
    }
  }
  return Result::success({header, m});
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
  store_vec3(state.position, payload + kPositionAt);
  store_le_f64(state.orientation.w, payload + kOrientationAt);
  store_le_f64(state.orientation.x, payload + kOrientationAt + 8);
  store_le_f64(state.orientation.y, payload + kOrientationAt + 16);
  store_le_f64(state.orientation.z, payload + kOrientationAt + 24);
  return kDeviceStateFrameSize;
}

std::size_t encode(const ForceModel& model, uint32_t sequence, uint64_t timestamp_us,
                   std::span<uint8_t> out) {
  if (out.size() < kForceModelFrameSize) return 0;
  uint8_t* frame = out.data();
  store_header({MessageType::ForceModel, 0, kForceModelPayloadSize, sequence, timestamp_us}, frame);
  uint8_t* payload = frame + kHeaderSize;
  payload[kModelDeviceIndexAt] = model.device_index;
  store_vec3(model.reference_position, payload + kReferenceAt);
  store_vec3(model.force, payload + kForceAt);
  for (std::size_t i = 0; i < model.stiffness.size(); ++i) {
    store_le_f64(model.stiffness[i], payload + kStiffnessAt + 8 * i);
  }
  store_le(model.state_timestamp_us, payload + kStateTimestampAt);
  store_le_f64(model.sim_time_s, payload + kSimTimeAt);
  return kForceModelFrameSize;
}

DecodeResult decode(std::span<const uint8_t> frame) {
  FrameHeader header;
  if (auto failure =
          check_header<DecodeResult>(frame, MessageType::DeviceState, "server", header)) {
    return *failure;
  }
  return decode_device_state(header, frame.data() + kHeaderSize);
}

ForceModelDecodeResult decode_force_model(std::span<const uint8_t> frame) {
  FrameHeader header;
  if (auto failure =
          check_header<ForceModelDecodeResult>(frame, MessageType::ForceModel, "agent", header)) {
    return *failure;
  }
  return decode_model_payload(header, frame.data() + kHeaderSize);
}

template <typename Message>
BasicDecodeResult<Message> BasicDecodeResult<Message>::success(const Message& message) {
  BasicDecodeResult result;
  result.message_ = message;
  return result;
}

template <typename Message>
BasicDecodeResult<Message> BasicDecodeResult<Message>::failure(DecodeErrc error, const char* format,
                                                               ...) {
  BasicDecodeResult result;
  result.error_ = error;
  va_list args;
  va_start(args, format);
  const int written = std::vsnprintf(result.reason_.data(), result.reason_.size(), format, args);
  va_end(args);
  // vsnprintf reports the untruncated length; the buffer holds at most size - 1 characters.
  result.reason_size_ = std::min<std::size_t>(written < 0 ? 0 : written, kMaxCloseReasonSize);
  return result;
}

template class BasicDecodeResult<DeviceStateMessage>;
template class BasicDecodeResult<ForceModelMessage>;

}  // namespace incise::devices
