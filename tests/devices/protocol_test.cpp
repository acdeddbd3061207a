// Binary framing: devices/protocol.h.

#include "devices/protocol.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "allocation_counter.h"
#include "devices/little_endian.h"
#include "tests/support/protocol_checks.h"

namespace incise::devices {
namespace {

using Frame = std::vector<uint8_t>;

DeviceState sample_state() {
  DeviceState s;
  s.device_index = 1;
  s.buttons = 0b101;
  s.jaw = 0.5f;
  s.position = {1.0, -0.25, 0.125};
  s.orientation = {1.0, 0.0, 0.0, 0.0};
  return s;
}

Frame encoded(const DeviceState& state, uint32_t sequence = 7, uint64_t t_us = 123456) {
  Frame frame(kDeviceStateFrameSize);
  EXPECT_EQ(encode(state, sequence, t_us, frame), kDeviceStateFrameSize);
  return frame;
}

// Bit patterns, so that -0.0 and 0.0 differ and NaN equals itself.
void expect_bit_equal(const DeviceState& a, const DeviceState& b) {
  EXPECT_EQ(a.device_index, b.device_index);
  EXPECT_EQ(a.buttons, b.buttons);
  EXPECT_EQ(std::bit_cast<uint32_t>(a.jaw), std::bit_cast<uint32_t>(b.jaw));
  const double fa[] = {a.position.x,    a.position.y,    a.position.z,   a.orientation.w,
                       a.orientation.x, a.orientation.y, a.orientation.z};
  const double fb[] = {b.position.x,    b.position.y,    b.position.z,   b.orientation.w,
                       b.orientation.x, b.orientation.y, b.orientation.z};
  for (int i = 0; i < 7; ++i)
    EXPECT_EQ(std::bit_cast<uint64_t>(fa[i]), std::bit_cast<uint64_t>(fb[i]));
}

void expect_error(const Frame& frame, DecodeErrc error, std::string_view reason = {}) {
  test::expect_decode_error(decode(frame), error, reason);
}

TEST(Protocol, RoundTripOfRandomStatesIsBitExact) {
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> metres(-0.5, 0.5);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    DeviceState s;
    s.device_index = static_cast<uint8_t>(rng() % kMaxStationDevices);
    s.buttons = static_cast<uint8_t>(rng());
    s.jaw = (i % 10 == 0) ? static_cast<float>(i % 20 == 0) : unit(rng);  // include 0 and 1
    s.position = {metres(rng), metres(rng), (i % 7 == 0) ? -0.0 : metres(rng)};
    Quat q{gauss(rng), gauss(rng), gauss(rng), gauss(rng)};
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    s.orientation = {q.w / n, q.x / n, q.y / n, q.z / n};
    const auto sequence = static_cast<uint32_t>(rng());
    const uint64_t t_us = rng();

    const Frame frame = encoded(s, sequence, t_us);
    const DecodeResult result = decode(frame);
    ASSERT_TRUE(result.ok()) << result.reason();
    EXPECT_TRUE(result.reason().empty());
    const FrameHeader& h = result.message().header;
    EXPECT_EQ(h.type, MessageType::DeviceState);
    EXPECT_EQ(h.flags, 0);
    EXPECT_EQ(h.payload_length, kDeviceStatePayloadSize);
    EXPECT_EQ(h.sequence, sequence);
    EXPECT_EQ(h.timestamp_us, t_us);
    expect_bit_equal(result.message().state, s);
  }
}

TEST(Protocol, EncodeAndDecodeDoNotAllocate) {
  std::array<uint8_t, kDeviceStateFrameSize> frame{};
  DeviceState bad = sample_state();
  bad.position.y = std::numeric_limits<double>::quiet_NaN();
  std::array<uint8_t, kDeviceStateFrameSize> bad_frame{};
  const std::size_t before = testing::allocation_count();
  std::size_t written = encode(sample_state(), 1, 2, frame);
  written += encode(bad, 3, 4, bad_frame);
  const DecodeResult good = decode(frame);
  const DecodeResult rejected = decode(bad_frame);
  const DecodeResult truncated = decode(std::span(frame).first(10));
  EXPECT_EQ(testing::allocation_count(), before);
  EXPECT_EQ(written, 2 * kDeviceStateFrameSize);
  EXPECT_TRUE(good.ok());
  EXPECT_EQ(rejected.reason(), "position.y is not finite (nan)");
  EXPECT_EQ(truncated.error(), DecodeErrc::TooShort);
  // The counter does see allocations.
  const auto boxed = std::make_unique<int>(1);
  EXPECT_GT(testing::allocation_count(), before);
}

TEST(Protocol, BytesAreLittleEndianAtFixedOffsets) {
  DeviceState s = sample_state();
  s.device_index = 0xAB;
  s.buttons = 0xCD;
  const Frame f = encoded(s, 0x04030201u, 0x0C0B0A0908070605ull);
  ASSERT_EQ(f.size(), 82u);
  const Frame header = {0x01, 0x00,                                       // type
                        0x00, 0x00,                                       // flags
                        0x3E, 0x00, 0x00, 0x00,                           // payload length 62
                        0x01, 0x02, 0x03, 0x04,                           // sequence
                        0x05, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C};  // timestamp
  EXPECT_EQ(Frame(f.begin(), f.begin() + 20), header);
  EXPECT_EQ(f[20], 0xAB);                                                    // device index
  EXPECT_EQ(f[21], 0xCD);                                                    // buttons
  EXPECT_EQ(Frame(f.begin() + 22, f.begin() + 26), (Frame{0, 0, 0, 0x3F}));  // jaw 0.5f
  // position.x = 1.0 = 0x3FF0000000000000; position.y = -0.25 = 0xBFD0000000000000
  EXPECT_EQ(Frame(f.begin() + 26, f.begin() + 34), (Frame{0, 0, 0, 0, 0, 0, 0xF0, 0x3F}));
  EXPECT_EQ(Frame(f.begin() + 34, f.begin() + 42), (Frame{0, 0, 0, 0, 0, 0, 0xD0, 0xBF}));
  // position.z = 0.125 = 0x3FC0000000000000
  EXPECT_EQ(Frame(f.begin() + 42, f.begin() + 50), (Frame{0, 0, 0, 0, 0, 0, 0xC0, 0x3F}));
  // orientation w = 1.0, then x, y, z = 0.0
  EXPECT_EQ(Frame(f.begin() + 50, f.begin() + 58), (Frame{0, 0, 0, 0, 0, 0, 0xF0, 0x3F}));
  EXPECT_EQ(Frame(f.begin() + 58, f.end()), Frame(24, 0));
}

TEST(Protocol, EncodeIntoTooSmallBufferWritesNothing) {
  Frame small(kDeviceStateFrameSize - 1, 0xEE);
  EXPECT_EQ(encode(sample_state(), 1, 2, small), 0u);
  EXPECT_EQ(small, Frame(kDeviceStateFrameSize - 1, 0xEE));
  Frame large(200, 0xEE);
  EXPECT_EQ(encode(sample_state(), 1, 2, large), kDeviceStateFrameSize);
  EXPECT_EQ(large[kDeviceStateFrameSize], 0xEE);
}

TEST(Protocol, TruncatedAtEveryLength) {
  const Frame full = encoded(sample_state());
  for (std::size_t n = 0; n < full.size(); ++n) {
    SCOPED_TRACE(n);
    const Frame cut(full.begin(), full.begin() + n);
    expect_error(cut, n < kHeaderSize ? DecodeErrc::TooShort : DecodeErrc::LengthMismatch);
  }
  expect_error(Frame(full.begin(), full.begin() + 19), DecodeErrc::TooShort,
               "frame too short: 19 bytes, header is 20");
  expect_error(Frame(full.begin(), full.begin() + 50), DecodeErrc::LengthMismatch,
               "length mismatch: header says 62 payload bytes, frame has 30");
}

TEST(Protocol, LengthFieldMismatch) {
  for (uint32_t length : {0u, 61u, 63u, 0xFFFFFFFFu}) {
    Frame f = encoded(sample_state());
    store_le(length, f.data() + 4);
    expect_error(f, DecodeErrc::LengthMismatch);
  }
  Frame trailing = encoded(sample_state());
  trailing.push_back(0);
  expect_error(trailing, DecodeErrc::LengthMismatch,
               "length mismatch: header says 62 payload bytes, frame has 63");
}

TEST(Protocol, PayloadOfWrongSizeForItsType) {
  Frame f = encoded(sample_state());
  f.resize(kHeaderSize + 60);
  store_le(uint32_t{60}, f.data() + 4);  // consistent with the frame, wrong for DeviceState
  expect_error(f, DecodeErrc::BadPayloadSize, "DeviceState payload is 60 bytes, expected 62");
}

TEST(Protocol, UnknownAndReservedTypes) {
  for (uint16_t type : {0, 4, 99, 0xFFFF}) {
    Frame f = encoded(sample_state());
    store_le(type, f.data());
    expect_error(f, DecodeErrc::UnknownType, "unknown message type " + std::to_string(type));
  }
  Frame force_model = encoded(sample_state());
  store_le(uint16_t{2}, force_model.data());
  // A ForceModel goes the other way: the server never accepts one.
  expect_error(force_model, DecodeErrc::UnsupportedType,
               "message type 2 (ForceModel) goes server -> agent, not accepted by the server");
  Frame control = encoded(sample_state());
  store_le(uint16_t{3}, control.data());
  expect_error(control, DecodeErrc::UnsupportedType,
               "message type 3 (Control) is reserved, not accepted in protocol 1");
}

TEST(Protocol, FlagsMustBeZero) {
  Frame f = encoded(sample_state());
  store_le(uint16_t{0x0004}, f.data() + 2);
  expect_error(f, DecodeErrc::BadFlags, "flags 0x0004 set, protocol 1 defines none");
}

TEST(Protocol, NonFiniteValuesAreNamed) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    void (*poison)(DeviceState&, double);
    const char* name;
  };
  const Case cases[] = {
      {[](DeviceState& s, double v) { s.jaw = static_cast<float>(v); }, "jaw"},
      {[](DeviceState& s, double v) { s.position.x = v; }, "position.x"},
      {[](DeviceState& s, double v) { s.position.y = v; }, "position.y"},
      {[](DeviceState& s, double v) { s.position.z = v; }, "position.z"},
      {[](DeviceState& s, double v) { s.orientation.w = v; }, "orientation.w"},
      {[](DeviceState& s, double v) { s.orientation.x = v; }, "orientation.x"},
      {[](DeviceState& s, double v) { s.orientation.y = v; }, "orientation.y"},
      {[](DeviceState& s, double v) { s.orientation.z = v; }, "orientation.z"},
  };
  for (const Case& c : cases) {
    for (double bad : {nan, inf, -inf}) {
      SCOPED_TRACE(c.name);
      DeviceState s = sample_state();
      c.poison(s, bad);
      const DecodeResult result = decode(encoded(s));
      EXPECT_EQ(result.error(), DecodeErrc::NonFinite);
      EXPECT_TRUE(result.reason().starts_with(std::string(c.name) + " is not finite"))
          << result.reason();
    }
  }
}

TEST(Protocol, JawOutsideUnitInterval) {
  for (float jaw : {-0.01f, 1.01f, 100.0f}) {
    DeviceState s = sample_state();
    s.jaw = jaw;
    expect_error(encoded(s), DecodeErrc::JawOutOfRange);
  }
  DeviceState s = sample_state();
  s.jaw = 1.5f;
  expect_error(encoded(s), DecodeErrc::JawOutOfRange, "jaw 1.5 outside [0, 1]");
  // A station has two hands, devices 0 and 1.
  DeviceState third = sample_state();
  third.device_index = 2;
  expect_error(encoded(third), DecodeErrc::DeviceIndexOutOfRange,
               "device_index 2, a station has devices 0 and 1");
  for (float jaw : {0.0f, -0.0f, 1.0f}) {
    s.jaw = jaw;
    EXPECT_TRUE(decode(encoded(s)).ok()) << jaw;
  }
}

TEST(Protocol, QuaternionMustBeUnitWithinTolerance) {
  const double c = std::sqrt(0.5);
  DeviceState s = sample_state();
  s.orientation = {c * 1.01, c * 1.01, 0.0, 0.0};
  expect_error(encoded(s), DecodeErrc::NotUnitQuaternion,
               "orientation is not a unit quaternion: |q| = 1.01 (tolerance 0.001)");
  s.orientation = {0.0, 0.0, 0.0, 0.0};
  expect_error(encoded(s), DecodeErrc::NotUnitQuaternion);
  s.orientation = {0.9985, 0.0, 0.0, 0.0};
  expect_error(encoded(s), DecodeErrc::NotUnitQuaternion);
  s.orientation = {c * 1.0009, 0.0, -c * 1.0009, 0.0};  // inside the tolerance
  EXPECT_TRUE(decode(encoded(s)).ok());
}

}  // namespace
}  // namespace incise::devices
