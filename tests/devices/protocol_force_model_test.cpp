// ForceModel frames (server -> agent): devices/protocol.h.

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "allocation_counter.h"
#include "devices/little_endian.h"
#include "devices/protocol.h"
#include "tests/support/protocol_checks.h"

namespace incise::devices {
namespace {

using Frame = std::vector<uint8_t>;

ForceModel sample_model() {
  ForceModel m;
  m.device_index = 1;
  m.reference_position = {0.04, 0.04, 0.029};
  m.force = {0.5, -0.25, 3.0};
  m.stiffness = {500, 10, 0, 10, 500, 0, 0, 0, 2000};
  m.state_timestamp_us = 987654321;
  m.sim_time_s = 12.5;
  return m;
}

Frame encoded(const ForceModel& model, uint32_t sequence = 3, uint64_t t_us = 42) {
  Frame frame(kForceModelFrameSize);
  EXPECT_EQ(encode(model, sequence, t_us, frame), kForceModelFrameSize);
  return frame;
}

void expect_error(const Frame& frame, DecodeErrc error, std::string_view reason = {}) {
  test::expect_decode_error(decode_force_model(frame), error, reason);
}

TEST(ForceModelProtocol, RoundTripOfRandomModelsIsExact) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> metres(-0.5, 0.5);
  std::uniform_real_distribution<double> newtons(-50.0, 50.0);
  std::uniform_real_distribution<double> stiffness(-kMaxModelStiffness, kMaxModelStiffness);
  for (int i = 0; i < 1000; ++i) {
    ForceModel m;
    m.device_index = static_cast<uint8_t>(rng() % kMaxStationDevices);
    m.reference_position = {metres(rng), metres(rng), metres(rng)};
    m.force = {newtons(rng), newtons(rng), (i % 5 == 0) ? -0.0 : newtons(rng)};
    for (double& k : m.stiffness)
      k = stiffness(rng);
    if (i == 0) m.stiffness[4] = kMaxModelStiffness;  // the bounds are inclusive
    m.state_timestamp_us = rng();
    m.sim_time_s = std::abs(metres(rng)) * 1000.0;
    const auto sequence = static_cast<uint32_t>(rng());
    const uint64_t t_us = rng();

    const ForceModelDecodeResult result = decode_force_model(encoded(m, sequence, t_us));
    ASSERT_TRUE(result.ok()) << result.reason();
    const FrameHeader& h = result.message().header;
    EXPECT_EQ(h, (FrameHeader{MessageType::ForceModel, 0, kForceModelPayloadSize, sequence, t_us}));
    EXPECT_EQ(result.message().model, m);
    EXPECT_EQ(std::signbit(result.message().model.force.z), std::signbit(m.force.z));
  }
}

TEST(ForceModelProtocol, BytesAreLittleEndianAtTheDocumentedOffsets) {
  ForceModel m{};
  m.device_index = 0xAB;
  m.reference_position = {1.0, 0.0, 0.0};
  m.force = {0.0, -0.25, 0.0};
  m.stiffness[8] = 2.0;
  m.state_timestamp_us = 0x0807060504030201ull;
  m.sim_time_s = 0.125;
  const Frame f = encoded(m, 0x04030201u, 0x0C0B0A0908070605ull);
  ASSERT_EQ(f.size(), 157u);
  EXPECT_EQ(Frame(f.begin(), f.begin() + 8), (Frame{0x02, 0, 0, 0, 137, 0, 0, 0}));
  const std::size_t p = kHeaderSize;
  EXPECT_EQ(f[p + 0], 0xAB);
  EXPECT_EQ(load_le_f64(&f[p + 1]), 1.0);         // reference_position.x
  EXPECT_EQ(load_le_f64(&f[p + 25 + 8]), -0.25);  // force.y
  EXPECT_EQ(load_le_f64(&f[p + 49 + 64]), 2.0);   // stiffness[8] = K_zz
  EXPECT_EQ(Frame(f.begin() + p + 121, f.begin() + p + 129), (Frame{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(load_le_f64(&f[p + 129]), 0.125);  // sim_time_s
}

TEST(ForceModelProtocol, EncodeIntoTooSmallBufferWritesNothing) {
  Frame small(kForceModelFrameSize - 1, 0xEE);
  EXPECT_EQ(encode(sample_model(), 1, 2, small), 0u);
  EXPECT_EQ(small, Frame(kForceModelFrameSize - 1, 0xEE));
}

TEST(ForceModelProtocol, FramingErrors) {
  const Frame full = encoded(sample_model());
  expect_error(Frame(full.begin(), full.begin() + 19), DecodeErrc::TooShort,
               "frame too short: 19 bytes, header is 20");
  expect_error(Frame(full.begin(), full.begin() + 100), DecodeErrc::LengthMismatch,
               "length mismatch: header says 137 payload bytes, frame has 80");

  Frame short_payload(full.begin(), full.begin() + kHeaderSize + 136);
  store_le(uint32_t{136}, short_payload.data() + 4);
  expect_error(short_payload, DecodeErrc::BadPayloadSize,
               "ForceModel payload is 136 bytes, expected 137");

  Frame flags = full;
  store_le(uint16_t{1}, flags.data() + 2);
  expect_error(flags, DecodeErrc::BadFlags, "flags 0x0001 set, protocol 1 defines none");

  Frame unknown = full;
  store_le(uint16_t{9}, unknown.data());
  expect_error(unknown, DecodeErrc::UnknownType, "unknown message type 9");
}

TEST(ForceModelProtocol, EachSideAcceptsOnlyItsOwnDirection) {
  // The agent refuses a DeviceState (it only ever sends them) and reserved Control frames.
  std::array<uint8_t, kDeviceStateFrameSize> state{};
  ASSERT_EQ(encode(DeviceState{}, 0, 0, state), state.size());
  expect_error(Frame(state.begin(), state.end()), DecodeErrc::UnsupportedType,
               "message type 1 (DeviceState) goes agent -> server, not accepted by the agent");
  Frame control = encoded(sample_model());
  store_le(uint16_t{3}, control.data());
  expect_error(control, DecodeErrc::UnsupportedType,
               "message type 3 (Control) is reserved, not accepted in protocol 1");
  // And the server's decode() refuses a ForceModel.
  EXPECT_EQ(decode(encoded(sample_model())).error(), DecodeErrc::UnsupportedType);
}

TEST(ForceModelProtocol, NonFiniteValuesAreNamed) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double bad : {nan, inf, -inf}) {
    ForceModel m = sample_model();
    m.reference_position.y = bad;
    EXPECT_TRUE(
        decode_force_model(encoded(m)).reason().starts_with("reference_position.y is not finite"));
    m = sample_model();
    m.force.z = bad;
    EXPECT_TRUE(decode_force_model(encoded(m)).reason().starts_with("force.z is not finite"));
    m = sample_model();
    m.sim_time_s = bad;
    EXPECT_TRUE(decode_force_model(encoded(m)).reason().starts_with("sim_time_s is not finite"));
    for (std::size_t i = 0; i < 9; ++i) {
      m = sample_model();
      m.stiffness[i] = bad;
      const ForceModelDecodeResult result = decode_force_model(encoded(m));
      EXPECT_EQ(result.error(), DecodeErrc::NonFinite);
      EXPECT_TRUE(result.reason().starts_with("stiffness[" + std::to_string(i) + "] is not finite"))
          << result.reason();
    }
  }
  ForceModel m = sample_model();
  m.force.x = nan;
  expect_error(encoded(m), DecodeErrc::NonFinite, "force.x is not finite (nan)");
}

TEST(ForceModelProtocol, ForceAndStiffnessBounds) {
  ForceModel m = sample_model();
  m.force = {60.0, 0.0, 80.0};  // |f| = 100 N exactly: accepted
  EXPECT_TRUE(decode_force_model(encoded(m)).ok());
  m.force = {60.0, 0.0, 80.1};
  expect_error(encoded(m), DecodeErrc::ForceOutOfRange, "|force| 100.08 N exceeds 100 N");

  m = sample_model();
  m.device_index = 7;
  expect_error(encoded(m), DecodeErrc::DeviceIndexOutOfRange,
               "device_index 7, a station has devices 0 and 1");

  m = sample_model();
  m.stiffness[5] = -1.5e5;
  expect_error(encoded(m), DecodeErrc::StiffnessOutOfRange,
               "stiffness[5] -150000 N/m outside [-100000, 100000]");
  m.stiffness[5] = -kMaxModelStiffness;
  EXPECT_TRUE(decode_force_model(encoded(m)).ok());
}

TEST(ForceModelProtocol, EncodeAndDecodeDoNotAllocate) {
  std::array<uint8_t, kForceModelFrameSize> frame{};
  ForceModel bad = sample_model();
  bad.stiffness[7] = std::numeric_limits<double>::infinity();
  std::array<uint8_t, kForceModelFrameSize> bad_frame{};
  const std::size_t before = testing::allocation_count();
  std::size_t written = encode(sample_model(), 1, 2, frame);
  written += encode(bad, 3, 4, bad_frame);
  const ForceModelDecodeResult good = decode_force_model(frame);
  const ForceModelDecodeResult rejected = decode_force_model(bad_frame);
  EXPECT_EQ(testing::allocation_count(), before);
  EXPECT_EQ(written, 2 * kForceModelFrameSize);
  EXPECT_EQ(good.message().model, sample_model());
  EXPECT_EQ(rejected.reason(), "stiffness[7] is not finite (inf)");
}

}  // namespace
}  // namespace incise::devices
