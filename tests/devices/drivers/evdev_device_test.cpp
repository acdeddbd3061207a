// The 3D-mouse driver: devices/drivers/evdev_device.h. Events are fed through a non-blocking pipe,
// so the driver reads exactly what a real evdev node would deliver (and pipes can also split a
// record, which the driver must survive).

#include "devices/drivers/evdev_device.h"

#include <fcntl.h>
#include <linux/input.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>

#include "tests/devices/allocation_counter.h"

namespace incise::devices {
namespace {

constexpr double kDt = 0.001;  // the haptic loop's period [s]

EvdevSettings test_settings() {
  EvdevSettings s;
  s.max_speed_m_s = 0.04;
  s.max_rate_rad_s = 0.8;
  s.full_scale = 350.0;
  s.deadzone = 0.1;
  s.relative_hold_s = 0.1;
  s.start_position = {0.0, 0.0, 0.1};
  s.workspace_min = {-0.1, -0.1, 0.0};
  s.workspace_max = {0.1, 0.1, 0.2};
  return s;
}

// A device reading from a pipe, and the pipe's write end standing in for the kernel.
class Feed {
 public:
  explicit Feed(EvdevSettings settings = test_settings()) {
    int fds[2];
    if (::pipe2(fds, O_NONBLOCK | O_CLOEXEC) != 0) throw std::runtime_error("pipe2 failed");
    write_fd_ = fds[1];
    device_ = std::make_unique<EvdevDevice>(fds[0], settings, "evdev test");
  }
  ~Feed() { close_writer(); }

  EvdevDevice& device() { return *device_; }

  void raw(const void* bytes, std::size_t size) {
    ASSERT_EQ(::write(write_fd_, bytes, size), static_cast<ssize_t>(size));
  }
  void event(unsigned type, unsigned code, int value) {
    const input_event e = make(type, code, value);
    raw(&e, sizeof e);
  }
  void sync() { event(EV_SYN, SYN_REPORT, 0); }
  void close_writer() {
    if (write_fd_ >= 0) ::close(write_fd_);
    write_fd_ = -1;
  }

  // Polls every kDt over (t0, t1] and returns the last state.
  DeviceState run(double t0, double t1) {
    DeviceState s;
    const long steps = std::lround((t1 - t0) / kDt);
    for (long k = 1; k <= steps; ++k)
      s = device_->poll(t0 + k * kDt);
    return s;
  }

  static input_event make(unsigned type, unsigned code, int value) {
    input_event e{};
    e.type = static_cast<uint16_t>(type);
    e.code = static_cast<uint16_t>(code);
    e.value = value;
    return e;
  }

 private:
  int write_fd_ = -1;
  std::unique_ptr<EvdevDevice> device_;
};

void expect_near(const Vec3& a, const Vec3& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

double norm(const Quat& q) {
  return std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
}

Quat multiply(const Quat& a, const Quat& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

// The same rotation (q and -q), compared componentwise.
void expect_same_rotation(const Quat& a, const Quat& b, double tolerance) {
  const double sign = (a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z) < 0.0 ? -1.0 : 1.0;
  EXPECT_NEAR(a.w, sign * b.w, tolerance);
  EXPECT_NEAR(a.x, sign * b.x, tolerance);
  EXPECT_NEAR(a.y, sign * b.y, tolerance);
  EXPECT_NEAR(a.z, sign * b.z, tolerance);
}

TEST(EvdevDevice, ConstantDeflectionMovesTheTipAtTheCommandedSpeed) {
  Feed feed;
  EXPECT_EQ(feed.device().poll(0.0).position, (Vec3{0.0, 0.0, 0.1}));
  feed.event(EV_ABS, ABS_X, 175);
  feed.event(EV_ABS, ABS_Y, -70);
  feed.event(EV_ABS, ABS_Z, 350);
  feed.sync();
  // v = max_speed * d / full_scale per axis, for 0.25 s.
  const Vec3 after_first{0.04 * 0.5 * 0.25, 0.04 * -0.2 * 0.25, 0.1 + 0.04 * 1.0 * 0.25};
  expect_near(feed.run(0.0, 0.25).position, after_first, 1e-12);

  // Piecewise-constant deflection: x reverses at half the rate, y and z stop.
  feed.event(EV_ABS, ABS_X, -87);
  feed.event(EV_ABS, ABS_Y, 0);
  feed.event(EV_ABS, ABS_Z, 0);
  feed.sync();
  const DeviceState later = feed.run(0.25, 0.65);
  expect_near(later.position,
              {after_first.x - 0.04 * (87.0 / 350.0) * 0.4, after_first.y, after_first.z}, 1e-12);
  EXPECT_EQ(later.orientation, Quat{});
}

TEST(EvdevDevice, DeflectionBeyondFullScaleSaturates) {
  Feed feed;
  feed.device().poll(0.0);
  feed.event(EV_ABS, ABS_Y, 500);
  feed.sync();
  expect_near(feed.run(0.0, 0.1).position, {0.0, 0.04 * 0.1, 0.1}, 1e-12);
}

TEST(EvdevDevice, DeadzoneSuppressesSmallDeflections) {
  Feed feed;  // deadzone 0.1 = 35 counts
  feed.device().poll(0.0);
  feed.event(EV_ABS, ABS_X, 34);
  feed.event(EV_ABS, ABS_Y, -34);
  feed.event(EV_ABS, ABS_RZ, 30);
  feed.sync();
  const DeviceState still = feed.run(0.0, 0.5);
  EXPECT_EQ(still.position, (Vec3{0.0, 0.0, 0.1}));
  EXPECT_EQ(still.orientation, Quat{});
  // Just outside, the full (not rescaled) deflection applies.
  feed.event(EV_ABS, ABS_X, 36);
  feed.sync();
  expect_near(feed.run(0.5, 1.0).position, {0.04 * (36.0 / 350.0) * 0.5, 0.0, 0.1}, 1e-12);
}

TEST(EvdevDevice, ConstantRateTurnsByRateTimesTimeAboutThatAxis) {
  Feed feed;
  feed.device().poll(0.0);
  feed.event(EV_ABS, ABS_RZ, 175);  // 0.8 rad/s * 0.5 = 0.4 rad/s about z
  feed.sync();
  for (int k = 1; k <= 1000; ++k) {
    const Quat q = feed.device().poll(k * kDt).orientation;
    ASSERT_NEAR(norm(q), 1.0, 1e-14) << "at poll " << k;
  }
  const double angle = 0.4 * 1.0;
  expect_same_rotation(feed.device().poll(1.0).orientation,
                       {std::cos(angle / 2), 0.0, 0.0, std::sin(angle / 2)}, 1e-12);
  EXPECT_EQ(feed.device().poll(1.0).position, (Vec3{0.0, 0.0, 0.1}));
}

TEST(EvdevDevice, AngularVelocityIsInTheStationFrame) {
  // A quarter turn about x, then a quarter turn about z: station-frame rates compose as
  // q = qz * qx (the second turn is about the station's z, not the tool's rotated z).
  EvdevSettings settings = test_settings();
  settings.max_rate_rad_s = std::numbers::pi / 2;  // full deflection for 1 s = a quarter turn
  Feed feed(settings);
  feed.device().poll(0.0);
  feed.event(EV_ABS, ABS_RX, 350);
  feed.sync();
  feed.run(0.0, 1.0);
  feed.event(EV_ABS, ABS_RX, 0);
  feed.event(EV_ABS, ABS_RZ, 350);
  feed.sync();
  const Quat q = feed.run(1.0, 2.0).orientation;
  const double c = std::sqrt(0.5);
  expect_same_rotation(q, multiply({c, 0.0, 0.0, c}, {c, c, 0.0, 0.0}), 1e-12);
  EXPECT_NEAR(norm(q), 1.0, 1e-14);
}

TEST(EvdevDevice, AxisSignFlipsAnAxis) {
  EvdevSettings settings = test_settings();
  settings.axis_sign = {1, 1, -1, 1, 1, 1};  // a cap pressed down reports +z
  Feed feed(settings);
  feed.device().poll(0.0);
  feed.event(EV_ABS, ABS_Z, 350);
  feed.sync();
  expect_near(feed.run(0.0, 0.5).position, {0.0, 0.0, 0.1 - 0.04 * 0.5}, 1e-12);
}

TEST(EvdevDevice, WorkspaceClampHoldsAndReleasesAtOnce) {
  Feed feed;
  feed.device().poll(0.0);
  feed.event(EV_ABS, ABS_X, 350);
  feed.event(EV_ABS, ABS_Z, -350);
  feed.sync();
  // 0.04 m/s for 5 s would be 0.2 m; the box stops x at 0.1 and z at 0.
  for (int k = 1; k <= 5000; ++k) {
    const Vec3 p = feed.device().poll(k * kDt).position;
    ASSERT_LE(p.x, 0.1);
    ASSERT_GE(p.z, 0.0);
  }
  EXPECT_EQ(feed.device().poll(5.0).position, (Vec3{0.1, 0.0, 0.0}));
  // No wind-up: reversing moves away from the wall straight away.
  feed.event(EV_ABS, ABS_X, -350);
  feed.event(EV_ABS, ABS_Z, 0);
  feed.sync();
  expect_near(feed.run(5.0, 5.5).position, {0.1 - 0.04 * 0.5, 0.0, 0.0}, 1e-12);
}

TEST(EvdevDevice, RelativeAxesExpireAfterTheHoldTime) {
  // The input core drops zero-valued relative events, so a released cap is silence.
  Feed feed;
  feed.device().poll(0.0);
  feed.event(EV_REL, REL_X, 350);
  feed.event(EV_REL, REL_RY, 350);
  feed.sync();
  const DeviceState s = feed.run(0.0, 0.5);  // read at t = 0.001, so active over (0, 0.101]
  expect_near(s.position, {0.04 * 0.101, 0.0, 0.1}, 1e-12);
  const double angle = 0.8 * 0.101;
  expect_same_rotation(s.orientation, {std::cos(angle / 2), 0.0, std::sin(angle / 2), 0.0}, 1e-12);

  // A frame that reports only y leaves x's expiry alone; x keeps its own clock.
  feed.event(EV_REL, REL_X, -175);
  feed.sync();
  feed.device().poll(0.501);
  feed.event(EV_REL, REL_Y, 350);
  feed.sync();
  const DeviceState t = feed.run(0.501, 1.0);  // x active over (0.5, 0.601], y over (0.501, 0.602]
  expect_near(t.position, {0.04 * 0.101 - 0.04 * 0.5 * 0.101, 0.04 * 0.101, 0.1}, 1e-12);
}

TEST(EvdevDevice, EventsWaitForSynReport) {
  Feed feed;
  feed.device().poll(0.0);
  feed.event(EV_ABS, ABS_X, 350);
  feed.event(EV_KEY, BTN_0, 1);
  DeviceState s = feed.run(0.0, 0.1);
  EXPECT_EQ(s.position, (Vec3{0.0, 0.0, 0.1}));
  EXPECT_EQ(s.buttons, 0);
  feed.sync();
  s = feed.run(0.1, 0.2);
  expect_near(s.position, {0.04 * 0.1, 0.0, 0.1}, 1e-12);
  EXPECT_EQ(s.buttons, 1);
}

TEST(EvdevDevice, ButtonsSetAndClearTheirBits) {
  Feed feed;
  EXPECT_EQ(feed.device().capabilities().button_count, 8);
  EXPECT_FALSE(feed.device().capabilities().has_force_output);
  EXPECT_FALSE(feed.device().capabilities().has_jaw);
  EXPECT_EQ(feed.device().degrees_of_freedom(), 6);
  feed.event(EV_KEY, BTN_0, 1);
  feed.event(EV_KEY, BTN_1, 1);
  feed.event(EV_KEY, BTN_7, 1);
  feed.event(EV_KEY, BTN_8, 1);  // beyond the 8 bits: ignored
  feed.event(EV_KEY, KEY_A, 1);  // not a button: ignored
  feed.sync();
  EXPECT_EQ(feed.device().poll(0.0).buttons, 0b1000'0011);
  feed.event(EV_KEY, BTN_1, 0);
  feed.event(EV_KEY, BTN_RIGHT, 2);  // autorepeat counts as pressed; BTN_RIGHT is bit 1 too
  feed.event(EV_KEY, BTN_0, 0);
  feed.sync();
  EXPECT_EQ(feed.device().poll(0.001).buttons, 0b1000'0010);
  feed.event(EV_KEY, BTN_RIGHT, 0);
  feed.event(EV_KEY, BTN_7, 0);
  feed.sync();
  EXPECT_EQ(feed.device().poll(0.002).buttons, 0);
}

TEST(EvdevDevice, ButtonZeroCanToggleTheJaw) {
  EvdevSettings settings = test_settings();
  settings.button0_toggles_jaw = true;
  Feed feed(settings);
  EXPECT_TRUE(feed.device().capabilities().has_jaw);
  EXPECT_EQ(feed.device().degrees_of_freedom(), 7);
  EXPECT_EQ(feed.device().poll(0.0).jaw, 1.0f);  // starts open
  const float expected[] = {0.0f, 0.0f, 1.0f, 1.0f, 0.0f};
  for (int k = 0; k < 5; ++k) {
    feed.event(EV_KEY, BTN_0, k % 2 == 0 ? 1 : 0);  // press, release, press, ...
    feed.sync();
    EXPECT_EQ(feed.device().poll(0.001 * (k + 1)).jaw, expected[k]) << "event " << k;
  }
}

TEST(EvdevDevice, SplitRecordsAreReassembled) {
  Feed feed;
  feed.device().poll(0.0);
  input_event events[3] = {Feed::make(EV_ABS, ABS_Y, 350), Feed::make(EV_KEY, BTN_0, 1),
                           Feed::make(EV_SYN, SYN_REPORT, 0)};
  const auto* bytes = reinterpret_cast<const unsigned char*>(events);
  feed.raw(bytes, 10);  // half of the first record
  EXPECT_EQ(feed.device().poll(0.1).position, (Vec3{0.0, 0.0, 0.1}));
  feed.raw(bytes + 10, sizeof events - 15);  // the rest except the SYN_REPORT's tail
  EXPECT_EQ(feed.device().poll(0.2).buttons, 0);
  feed.raw(bytes + sizeof events - 5, 5);
  const DeviceState s = feed.device().poll(0.3);
  EXPECT_EQ(s.buttons, 1);
  expect_near(s.position, {0.0, 0.04 * 0.1, 0.1}, 1e-12);
  EXPECT_TRUE(feed.device().fault().empty());
}

TEST(EvdevDevice, ManyFramesInOnePollAreAllApplied) {
  // More records than one read() takes; the last frame's deflection wins.
  Feed feed;
  feed.device().poll(0.0);
  for (int k = 0; k < 300; ++k) {
    feed.event(EV_ABS, ABS_X, k);
    feed.sync();
  }
  feed.event(EV_ABS, ABS_X, -350);
  feed.sync();
  expect_near(feed.device().poll(0.1).position, {-0.04 * 0.1, 0.0, 0.1}, 1e-12);
}

TEST(EvdevDevice, SynDroppedSkipsToTheNextReportAndStops) {
  Feed feed;
  feed.device().poll(0.0);
  feed.event(EV_ABS, ABS_X, 350);
  feed.event(EV_KEY, BTN_1, 1);
  feed.sync();
  const Vec3 moved = feed.run(0.0, 0.1).position;
  feed.event(EV_SYN, SYN_DROPPED, 0);
  feed.event(EV_ABS, ABS_Y, 350);  // part of a broken frame: dropped
  feed.sync();
  // Without ioctls (a pipe) the driver cannot re-read the axes: it centres them, and keeps the
  // buttons.
  const DeviceState s = feed.run(0.1, 0.3);
  EXPECT_EQ(s.position, moved);
  EXPECT_EQ(s.buttons, 0b10);
  feed.event(EV_ABS, ABS_Y, 350);
  feed.sync();
  expect_near(feed.run(0.3, 0.4).position, {moved.x, 0.04 * 0.1, 0.1}, 1e-12);
}

TEST(EvdevDevice, EndOfInputFaultsAndFreezesThePose) {
  Feed feed;
  feed.device().poll(0.0);
  feed.event(EV_ABS, ABS_X, 350);
  feed.event(EV_ABS, ABS_RZ, 350);
  feed.sync();
  const DeviceState before = feed.run(0.0, 0.2);
  EXPECT_TRUE(feed.device().fault().empty());
  feed.close_writer();  // what the tests can do of an unplug; ENODEV takes the same path
  for (double t = 0.201; t < 0.5; t += 0.05) {
    EXPECT_EQ(feed.device().poll(t), before);
    EXPECT_EQ(feed.device().fault(), "evdev test: end of input");
  }
}

TEST(EvdevDevice, ReadErrorsFaultWithTheirCause) {
  int fds[2];
  ASSERT_EQ(::pipe2(fds, O_NONBLOCK | O_CLOEXEC), 0);
  ::close(fds[0]);
  EvdevDevice device(fds[1], test_settings(), "evdev wrong-end");  // write-only: read gives EBADF
  const DeviceState s = device.poll(0.0);
  EXPECT_EQ(device.fault(), "evdev wrong-end: read failed: Bad file descriptor");
  EXPECT_EQ(s.position, (Vec3{0.0, 0.0, 0.1}));
}

TEST(EvdevDevice, PollDoesNotAllocate) {
  Feed feed;
  feed.device().poll(0.0);
  for (int k = 0; k < 100; ++k) {
    feed.event(EV_ABS, static_cast<unsigned>(k % 6), 100 + k);
    feed.event(EV_KEY, BTN_0, k % 2);
    feed.sync();
  }
  feed.event(EV_REL, REL_RX, 300);
  const auto* bytes = reinterpret_cast<const unsigned char*>("\x00\x00\x00\x00\x00\x00\x00");
  feed.raw(bytes, 7);  // a partial record to carry over
  const std::size_t before = testing::allocation_count();
  DeviceState s;
  for (int k = 1; k <= 200; ++k)
    s = feed.device().poll(k * kDt);
  feed.close_writer();
  s = feed.device().poll(0.3);
  const std::string_view fault = feed.device().fault();
  EXPECT_EQ(testing::allocation_count(), before);
  EXPECT_EQ(fault, "evdev test: end of input");
  EXPECT_NEAR(norm(s.orientation), 1.0, 1e-14);
}

TEST(EvdevDevice, RejectsBadSettingsPrecisely) {
  EvdevSettings s = test_settings();
  EXPECT_EQ(check_evdev_settings(s), "");
  s.deadzone = 1.5;
  EXPECT_EQ(check_evdev_settings(s), "deadzone: 1.5 not in [0, 1)");
  s = test_settings();
  s.max_speed_m_s = -1.0;
  EXPECT_EQ(check_evdev_settings(s), "max_speed_m_s: must be finite and > 0, got -1");
  s = test_settings();
  s.full_scale = NAN;
  EXPECT_EQ(check_evdev_settings(s),
            "full_scale: must be finite and >= 0 (0 = automatic), got nan");
  s = test_settings();
  s.axis_sign[4] = 0;
  EXPECT_EQ(check_evdev_settings(s), "axis_sign[4]: must be 1 or -1, got 0");
  s = test_settings();
  s.workspace_min.y = 0.2;
  EXPECT_EQ(check_evdev_settings(s), "workspace: min.y 0.2 must be < max.y 0.1 (both finite)");
  s = test_settings();
  s.start_position.z = 0.3;
  EXPECT_EQ(check_evdev_settings(s), "start_position.z: 0.3 outside [0, 0.2]");

  int fds[2];
  ASSERT_EQ(::pipe2(fds, O_NONBLOCK | O_CLOEXEC), 0);
  ::close(fds[1]);
  try {
    EvdevDevice device(fds[0], s, "evdev test");
    FAIL() << "constructed with bad settings";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "evdev settings: start_position.z: 0.3 outside [0, 0.2]");
  }
  EXPECT_EQ(::fcntl(fds[0], F_GETFD), -1) << "the constructor closes the fd it was given";
}

TEST(EvdevDevice, OpenNamesThePathAndTheCause) {
  auto missing = EvdevDevice::open("/nonexistent/event0", test_settings());
  EXPECT_FALSE(missing);
  EXPECT_EQ(missing.error, "evdev /nonexistent/event0: No such file or directory");

  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("incise_evdev_" + std::to_string(::getpid()));
  std::ofstream(file) << "not a device";
  auto regular = EvdevDevice::open(file.string(), test_settings());
  std::filesystem::remove(file);
  EXPECT_FALSE(regular);
  EXPECT_EQ(regular.error, "evdev " + file.string() +
                               ": not an input event device (EVIOCGBIT: Inappropriate ioctl for "
                               "device)");

  EvdevSettings bad = test_settings();
  bad.deadzone = -0.1;
  EXPECT_EQ(EvdevDevice::open("/dev/input/event0", bad).error,
            "evdev settings: deadzone: -0.1 not in [0, 1)");
}

TEST(EvdevDiscovery, CapabilityBitmapsReadLikeTheKernelWritesThem) {
  for (int bit = 0; bit < 6; ++bit)
    EXPECT_TRUE(capability_bit("3f", bit)) << bit;
  EXPECT_FALSE(capability_bit("3f", 6));
  EXPECT_TRUE(capability_bit("1 0\n", 64));
  EXPECT_FALSE(capability_bit("1 0\n", 0));
  EXPECT_FALSE(capability_bit("1 0", 128));
  EXPECT_TRUE(capability_bit("1000000000000 0 0 0 0", BTN_SOUTH));  // 0x130 = word 4, bit 48
  EXPECT_FALSE(capability_bit("", 0));
  EXPECT_FALSE(capability_bit("zz", 0));
}

TEST(EvdevDiscovery, FindsSixAxisDevicesButNotMiceOrGamepads) {
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / ("incise_sysfs_" + std::to_string(::getpid()));
  const fs::path sys = root / "class_input";
  const fs::path dev = root / "dev_input";
  fs::create_directories(dev);
  auto add = [&](const std::string& node, const std::string& name, const std::string& abs,
                 const std::string& rel, const std::string& key) {
    const fs::path caps = sys / node / "device" / "capabilities";
    fs::create_directories(caps);
    std::ofstream(sys / node / "device" / "name") << name << "\n";
    std::ofstream(caps / "abs") << abs << "\n";
    std::ofstream(caps / "rel") << rel << "\n";
    std::ofstream(caps / "key") << key << "\n";
  };
  add("event3", "3Dconnexion SpaceMouse Compact", "3f", "0", "3 0 0 0 0");
  add("event4", "3Dconnexion SpaceNavigator", "0", "3f", "3 0 0 0 0");
  add("event5", "Gamepad", "3003f", "0", "1000000000000 0 0 0 0");
  add("event6", "Optical Mouse", "0", "143", "1f0000 0 0 0 0");
  add("input9", "not an event node", "3f", "0", "0");
  std::ofstream(dev / "event3") << "";  // event4's node is missing: not readable

  const auto found = find_3d_mice(sys, dev);
  fs::remove_all(root);
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].path, (dev / "event3").string());
  EXPECT_EQ(found[0].name, "3Dconnexion SpaceMouse Compact");
  EXPECT_FALSE(found[0].relative_axes);
  EXPECT_TRUE(found[0].readable);
  EXPECT_EQ(found[1].path, (dev / "event4").string());
  EXPECT_TRUE(found[1].relative_axes);
  EXPECT_FALSE(found[1].readable);
}

}  // namespace
}  // namespace incise::devices
