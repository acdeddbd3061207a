// Device-state logs and their replay: devices/state_log.h. Files live in a fresh temporary
// directory per test.

#include "devices/state_log.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>

#include "tests/support/temp_dir.h"

namespace incise::devices {
namespace {

class StateLogTest : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_.path() / name).string(); }

  // Writes samples with StateLogWriter and returns the file's path.
  std::string write_log(const std::string& name, const std::vector<TimedSample>& samples) {
    const std::string file = path(name);
    auto writer = StateLogWriter::create(file);
    EXPECT_TRUE(writer) << writer.error;
    for (const TimedSample& s : samples)
      EXPECT_TRUE((*writer.value)->write(s.state, s.timestamp_us));
    EXPECT_EQ((*writer.value)->written(), samples.size());
    return file;
  }

  void write_bytes(const std::string& file, const std::vector<uint8_t>& bytes) {
    std::ofstream out(file, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
  }

  incise::test::TempDir dir_{"incise-state-log"};
};

// ReplayDevice's tests, in the same temporary directory set-up.
class ReplayDeviceTest : public StateLogTest {};

DeviceState random_state(std::mt19937& random, uint8_t device) {
  std::uniform_real_distribution<double> position(-0.2, 0.2);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<float> jaw(0.0f, 1.0f);
  DeviceState s;
  s.device_index = device;
  s.buttons = static_cast<uint8_t>(random() & 0xff);
  s.jaw = jaw(random);
  s.position = {position(random), position(random), position(random)};
  Quat q{normal(random), normal(random), normal(random), normal(random)};
  const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  s.orientation = {q.w / norm, q.x / norm, q.y / norm, q.z / norm};
  return s;
}

// Two hands interleaved at 500 Hz each, device 1 a little behind device 0.
std::vector<TimedSample> two_hand_samples(int per_device, unsigned seed) {
  std::mt19937 random(seed);
  std::vector<TimedSample> samples;
  for (int i = 0; i < per_device; ++i) {
    samples.push_back({1000 + 2000 * static_cast<uint64_t>(i), random_state(random, 0)});
    samples.push_back({700 + 2000 * static_cast<uint64_t>(i), random_state(random, 1)});
  }
  return samples;
}

DeviceState state_at(double x, uint8_t device = 0) {
  DeviceState s;
  s.device_index = device;
  s.position = {x, 0.0, 0.0};
  return s;
}

TEST_F(StateLogTest, ReadsBackExactlyWhatWasWritten) {
  const std::vector<TimedSample> samples = two_hand_samples(250, 3);
  const std::string file = write_log("two.log", samples);
  EXPECT_EQ(std::filesystem::file_size(file), samples.size() * kDeviceStateFrameSize);
  const auto read = read_state_log(file);
  ASSERT_TRUE(read) << read.error;
  ASSERT_EQ(read.value->size(), samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ((*read.value)[i].timestamp_us, samples[i].timestamp_us) << i;
    EXPECT_EQ((*read.value)[i].state, samples[i].state) << i;  // bit for bit
  }
}

TEST_F(StateLogTest, CreateNamesTheFileAndTheSystemError) {
  const std::string file = path("no/such/dir.log");
  const auto writer = StateLogWriter::create(file);
  ASSERT_FALSE(writer);
  EXPECT_EQ(writer.error, "record-states " + file + ": No such file or directory");
}

TEST_F(StateLogTest, MissingAndEmptyFilesAreErrors) {
  const std::string missing = path("missing.log");
  EXPECT_EQ(read_state_log(missing).error, "replay " + missing + ": cannot open");
  const std::string empty = path("empty.log");
  write_bytes(empty, {});
  EXPECT_EQ(read_state_log(empty).error, "replay " + empty + ": empty");
}

TEST_F(StateLogTest, APartialFrameIsAnError) {
  const std::string file = write_log("partial.log", {{0, state_at(0.0)}, {10, state_at(0.1)}});
  {
    std::ofstream out(file, std::ios::binary | std::ios::app);
    out.write("abcde", 5);
  }
  EXPECT_EQ(read_state_log(file).error,
            "replay " + file + ": 169 bytes is not a whole number of 82-byte frames");
}

TEST_F(StateLogTest, ACorruptFrameIsNamedByItsNumber) {
  DeviceState bad = state_at(0.2);
  bad.jaw = 1.5f;  // written as given, refused by the decoder
  const std::string file =
      write_log("corrupt.log", {{0, state_at(0.0)}, {10, state_at(0.1)}, {20, bad}});
  EXPECT_EQ(read_state_log(file).error, "replay " + file + ": frame 2: jaw 1.5 outside [0, 1]");

  DeviceState not_unit = state_at(0.0);
  not_unit.orientation = {0.5, 0.0, 0.0, 0.0};
  const std::string second = write_log("quaternion.log", {{0, not_unit}});
  EXPECT_EQ(read_state_log(second).error,
            "replay " + second +
                ": frame 0: orientation is not a unit quaternion: |q| = 0.5 (tolerance 0.001)");
}

TEST_F(StateLogTest, TimestampsMustNotGoBackPerDevice) {
  // Device 1 may be behind device 0 (each device's clock is checked on its own) ...
  const std::string ok = write_log(
      "ok.log", {{100, state_at(0.0, 0)}, {50, state_at(0.0, 1)}, {100, state_at(0.1, 0)}});
  EXPECT_TRUE(read_state_log(ok));
  // ... but no device's may go back.
  const std::string back = write_log(
      "back.log", {{100, state_at(0.0, 0)}, {50, state_at(0.0, 1)}, {90, state_at(0.1, 0)}});
  EXPECT_EQ(read_state_log(back).error,
            "replay " + back + ": frame 2: timestamp 90 us goes back (previous 100 us)");
}

TEST_F(ReplayDeviceTest, OpenParsesItsOptions) {
  const std::string file = write_log("two.log", two_hand_samples(3, 5));
  for (const std::string& argument : {file, file + ",device=0", file + ",once", file + ",device=1",
                                      file + ",device=1,once", file + ",once,device=1"}) {
    const auto device = ReplayDevice::open(argument);
    ASSERT_TRUE(device) << argument << ": " << device.error;
    const bool second = argument.find("device=1") != std::string::npos;
    EXPECT_EQ((*device.value)->name(),
              "replay (" + file + ", device " + std::string(second ? "1" : "0") + ")");
  }
  EXPECT_EQ(ReplayDevice::open(file + ",speed=2").error,
            "replay " + file + ",speed=2: unknown option 'speed=2' (device=0, device=1 or once)");
  EXPECT_EQ(ReplayDevice::open(file + ",device=2").error,
            "replay " + file + ",device=2: unknown option 'device=2' (device=0, device=1 or once)");
  EXPECT_EQ(ReplayDevice::open(",once").error,
            "replay: needs a file, replay:FILE[,device=N][,once]");
  EXPECT_EQ(ReplayDevice::open(path("missing.log") + ",once").error,
            "replay " + path("missing.log") + ": cannot open");
  const std::string one_hand = write_log("one.log", {{0, state_at(0.0)}});
  EXPECT_EQ(ReplayDevice::open(one_hand + ",device=1").error,
            "replay " + one_hand + ": no states of device 1");
}

TEST_F(ReplayDeviceTest, OpenPlaysTheChosenDevice) {
  const std::vector<TimedSample> samples = two_hand_samples(3, 9);
  const std::string file = write_log("two.log", samples);
  const auto device = ReplayDevice::open(file + ",device=1,once");
  ASSERT_TRUE(device) << device.error;
  // Device 1's samples are at 700, 2700, 4700 us: t = 0 is the first.
  for (int i = 0; i < 3; ++i) {
    DeviceState expected = samples[2 * i + 1].state;
    expected.device_index = 0;  // the haptic loop numbers the station's devices itself
    EXPECT_EQ((*device.value)->poll(0.002 * i), expected) << i;
  }
}

// Samples at 1000, 1500 and 3000 us: the replay's t = 0 is 1000 us.
std::vector<TimedSample> three_samples(uint8_t device) {
  return {
      {1000, state_at(0.0, device)}, {1500, state_at(0.1, device)}, {3000, state_at(0.2, device)}};
}

TEST_F(ReplayDeviceTest, PollIsSampleAndHoldRelativeToTheFirstSample) {
  ReplayDevice replay(three_samples(1), /*loop=*/false, "test");
  const auto x_at = [&](double t) { return replay.poll(t).position.x; };
  EXPECT_EQ(x_at(-1.0), 0.0);  // before the start: the first sample
  EXPECT_EQ(x_at(0.0), 0.0);
  EXPECT_EQ(x_at(0.000499), 0.0);
  EXPECT_EQ(x_at(0.0005), 0.1);  // at a sample's time: that sample
  EXPECT_EQ(x_at(0.001999), 0.1);
  EXPECT_EQ(x_at(0.002), 0.2);
  // Without loop the last sample is held for ever.
  EXPECT_EQ(x_at(0.0021), 0.2);
  EXPECT_EQ(x_at(1e4), 0.2);
  EXPECT_EQ(replay.poll(0.0005).device_index, 0);
}

TEST_F(ReplayDeviceTest, PollLoopsAfterTheEnd) {
  ReplayDevice replay(three_samples(0), /*loop=*/true, "test");
  const auto x_at = [&](double t) { return replay.poll(t).position.x; };
  // The cycle is the span from first to last sample plus one mean sample interval (the last
  // sample is held as long as the others): 2000 + 1000 us, then the first sample again.
  const double cycle = 0.003;
  EXPECT_EQ(x_at(0.002), 0.2);
  for (int n = 1; n <= 3; ++n) {
    EXPECT_EQ(x_at(n * cycle), 0.0) << n;
    EXPECT_EQ(x_at(n * cycle + 0.000499), 0.0) << n;
    EXPECT_EQ(x_at(n * cycle + 0.0005), 0.1) << n;
    EXPECT_EQ(x_at(n * cycle + 0.002), 0.2) << n;
    EXPECT_EQ(x_at(n * cycle + 0.002999), 0.2) << n;
  }
  // A single sample is held, looping or not.
  ReplayDevice single({{42, state_at(0.3)}}, /*loop=*/true, "test");
  EXPECT_EQ(single.poll(0.0).position.x, 0.3);
  EXPECT_EQ(single.poll(7.5).position.x, 0.3);
}

}  // namespace
}  // namespace incise::devices
