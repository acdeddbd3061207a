#pragma once
// A force-less 6-DOF driver for 3D mice (3Dconnexion SpaceMouse and alike) through Linux evdev
// (<linux/input.h>, no extra library).
//
// A 3D mouse is a rate-control device: the cap's deflection on each axis commands a velocity, and
// the driver integrates it into a tool pose. Per axis i, with n_i = deflection_i / full_scale_i
// clamped to [-1, 1] and set to 0 when |n_i| < deadzone:
//   position_i += max_speed_m_s * n_i * dt              (then clamped to the workspace box)
//   omega_i     = max_rate_rad_s * n_i                  (station frame)
//   orientation = exp(omega * dt / 2) * orientation     (renormalised)
// The angular velocity is applied in the station frame (left multiplication): a 3D mouse sits on
// the desk, so twisting its cap about z turns the tool about the station's z whatever the tool's
// current orientation.
//
// Timing: poll(t) first applies every complete event frame (up to EV_SYN SYN_REPORT) that arrived
// since the previous poll, then integrates over (t_previous, t] with the resulting deflection. A
// deflection is thus in effect from the poll before the one that reads it, which is exact when the
// deflection only changes between polls and never lags by a tick.
//
// Absolute axes (EV_ABS ABS_X .. ABS_RZ) hold their last value. Relative axes (EV_REL REL_X ..
// REL_RZ, older SpaceNavigators) report the deflection too, but the input core drops zero-valued
// relative events, so a cap back at rest is only seen as silence: a relative axis reads 0 once
// relative_hold_s has passed since the frame that last reported it.
//
// Buttons (EV_KEY) map to DeviceState::buttons: BTN_0 .. BTN_7 to bits 0 .. 7, and BTN_LEFT,
// BTN_RIGHT, BTN_MIDDLE, BTN_SIDE, BTN_EXTRA, BTN_FORWARD, BTN_BACK, BTN_TASK to bits 0 .. 7 (3D
// mice use one family or the other). Other keys are ignored. With button0_toggles_jaw, each press
// of button 0 toggles the jaw between open (1, the start) and closed (0), so a grasper can be used.

#include <array>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "devices/device.h"
#include "devices/parse_result.h"

namespace incise::devices {

// The logical range of 3Dconnexion devices' axes (-350 .. 350 counts).
inline constexpr double kSpaceMouseFullScale = 350.0;

struct EvdevSettings {
  double max_speed_m_s = 0.05;   // tip speed at full deflection [m/s]
  double max_rate_rad_s = 1.0;   // angular rate at full deflection [rad/s]
  double full_scale = 0.0;       // counts at full deflection on every axis; 0 = automatic: each
                                 // absolute axis's range from EVIOCGABS in open() (centre
                                 // (min + max) / 2, half range (max - min) / 2), otherwise
                                 // kSpaceMouseFullScale
  double deadzone = 0.05;        // |deflection| / full_scale below this reads as 0, in [0, 1)
  double relative_hold_s = 0.1;  // a relative axis's value expires this long after it was sent [s]
  // +1 or -1 per axis (x, y, z, rx, ry, rz), to turn the device's axes into the station frame's.
  // Devices differ (3Dconnexion caps report +z when pressed down); check with evtest.
  std::array<int, 6> axis_sign = {1, 1, 1, 1, 1, 1};
  bool button0_toggles_jaw = false;
  Vec3 start_position{0.0, 0.0, 0.1};   // [m], inside the workspace box
  Vec3 workspace_min{-0.1, -0.1, 0.0};  // the tip is clamped to this box [m]
  Vec3 workspace_max{0.1, 0.1, 0.2};
};

// Empty if the settings are usable; else the first problem, e.g. `deadzone: 1.5 not in [0, 1)`.
std::string check_evdev_settings(const EvdevSettings& settings);

class EvdevDevice final : public Device {
 public:
  // Opens path O_RDONLY | O_NONBLOCK and checks with EVIOCGBIT that it has six absolute or six
  // relative axes. Errors name the path and the cause, e.g.
  // `evdev /dev/input/event5: Permission denied` or
  // `evdev /dev/input/event5: has no 6-axis input (not a 3D mouse?)`. An empty path opens the
  // first readable device find_3d_mice() lists.
  static ParseResult<std::unique_ptr<EvdevDevice>> open(const std::string& path,
                                                        EvdevSettings settings);

  // Takes ownership of fd, which must be non-blocking and deliver struct input_event records (an
  // evdev node, or a pipe in tests). Makes no ioctl: full_scale 0 means kSpaceMouseFullScale and
  // capabilities() reports 8 buttons. Throws std::invalid_argument for bad settings (the fd is
  // closed then too).
  EvdevDevice(int fd, EvdevSettings settings, std::string name);
  ~EvdevDevice() override;
  EvdevDevice(const EvdevDevice&) = delete;
  EvdevDevice& operator=(const EvdevDevice&) = delete;

  std::string_view name() const override { return name_; }
  int degrees_of_freedom() const override { return settings_.button0_toggles_jaw ? 7 : 6; }
  DeviceCapabilities capabilities() const override;

  // Reads what is pending without blocking or allocating (a bounded number of read() calls into a
  // fixed buffer), applies complete frames and integrates. After a fault the last pose is returned
  // and the fd is no longer read.
  DeviceState poll(double t) override;

  // "<name>: device unplugged" (ENODEV), "<name>: end of input" (EOF, e.g. a closed pipe), or
  // "<name>: read failed: <strerror>"; empty while working. open() names a device
  // "evdev <path> (<device name>)".
  std::string_view fault() const override { return fault_; }

 private:
  static constexpr std::size_t kEventBufferSize = 64;  // input_event records per read()
  static constexpr int kMaxReadsPerPoll = 16;          // bounds the work of one poll

  struct Axes {
    std::array<double, 6> value{};  // raw counts
    std::array<bool, 6> relative{};
  };

  void apply_event(unsigned type, unsigned code, int value, double t);
  void commit_frame(double t);
  void set_buttons(uint8_t buttons);
  void resynchronise();
  void integrate(double t0, double t1);
  double normalised(int axis, double value) const;
  void set_fault(const char* what, int error_number);

  int fd_ = -1;
  EvdevSettings settings_;
  std::string name_;
  bool can_query_ = false;  // fd is a real evdev node (opened by open()), so ioctls work
  int button_count_ = 8;
  std::array<double, 6> centre_{};
  std::array<double, 6> half_range_{};

  // The read buffer (24 = sizeof(input_event) on 64-bit Linux). Between polls it holds only the
  // first pending_bytes_ bytes of an incomplete record: pipes can split records.
  alignas(8) std::array<unsigned char, kEventBufferSize * 24> bytes_{};
  std::size_t pending_bytes_ = 0;

  Axes pending_axes_;     // what the current frame has said so far
  unsigned touched_ = 0;  // bit i: the current frame set axis i
  uint8_t pending_buttons_ = 0;
  bool dropping_ = false;  // after SYN_DROPPED: ignore events up to and including SYN_REPORT
  Axes axes_;              // the committed deflection
  std::array<double, 6> expires_{};  // time after which a relative axis reads 0

  DeviceState state_;
  bool has_time_ = false;
  double last_t_ = 0.0;

  std::array<char, 256> fault_text_{};
  std::string_view fault_;
};

// A 6-axis input device found under /dev/input.
struct EvdevCandidate {
  std::string path;  // e.g. /dev/input/event5
  std::string name;  // the device's name, e.g. "3Dconnexion SpaceMouse Compact"
  bool relative_axes = false;
  bool readable = false;  // false: open() would fail with Permission denied; see docs
};

// Lists the devices with six absolute or six relative axes (and that are not joysticks or
// gamepads), from sysfs, which needs no permission on the device nodes. Sorted by path. Not for
// the haptic loop: it allocates and reads files.
std::vector<EvdevCandidate> find_3d_mice(
    const std::filesystem::path& sysfs_input = "/sys/class/input",
    const std::filesystem::path& dev_input = "/dev/input");

// Bit `bit` of a sysfs capability bitmap, e.g. "10000 0 3f": hex words of 64 bits, most
// significant first. False for bits beyond the words given or for malformed text.
bool capability_bit(std::string_view bitmap, int bit);

}  // namespace incise::devices
