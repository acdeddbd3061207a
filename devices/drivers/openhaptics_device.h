#pragma once
// A driver for 3D Systems' grounded haptic devices (Touch, Touch X, Phantom Premium) through the
// OpenHaptics HD API. Compiled only when the SDK is found (CMake option INCISE_WITH_OPENHAPTICS,
// OFF by default); this header itself needs no SDK header.
//
// Built against exactly this part of HD/hd.h (tests/devices/drivers/fake_hd/HD/hd.h declares it,
// for a compile-only check without the SDK):
//   hdInitDevice(HD_DEFAULT_DEVICE or a configuration name) -> HHD
//   hdGetError() -> HDErrorInfo {errorCode, internalErrorCode, hHD}, HD_DEVICE_ERROR(e),
//   hdGetErrorString(code)
//   hdEnable(HD_FORCE_OUTPUT), hdStartScheduler(), hdStopScheduler(), hdDisableDevice(HHD)
//   hdBeginFrame(HHD), hdEndFrame(HHD)
//   hdGetDoublev(HD_CURRENT_POSITION, double[3])    [mm]
//   hdGetDoublev(HD_CURRENT_TRANSFORM, double[16])  column-major, translation in [mm]
//   hdGetIntegerv(HD_CURRENT_BUTTONS, int*)          bit i = button i + 1
//   hdSetDoublev(HD_CURRENT_FORCE, double[3])        [N]
//   hdGetDoublev(HD_NOMINAL_MAX_FORCE, double*)      [N]
//
// Frames: one HD frame per poll(). poll() begins a frame, reads position, transform and buttons,
// writes the force that set_force() stored since the previous poll, and ends the frame. The force
// computed in tick k therefore reaches the motors in tick k + 1 (1 ms at 1 kHz): one frame per tick
// keeps the SDK's one-frame-per-servo-tick rhythm, and set_force() makes no SDK call at all.
//
// Frame: positions and forces are in the device's own frame (x right, y up, z toward the user,
// origin at the workspace centre), converted to metres; the station kinematics maps it further.
//
// Limits of this skeleton (see docs/device_drivers.md): one device per process (the HD scheduler
// is process-wide and hdMakeCurrentDevice is outside the stated API), and frames run on the
// caller's thread rather than in an HD scheduler callback, which must be verified on hardware.

#include <array>
#include <memory>
#include <string>
#include <string_view>

#include "devices/device.h"
#include "devices/parse_result.h"

namespace incise::devices {

struct OpenHapticsSettings {
  std::string device_name;     // an OpenHaptics configuration name; empty = HD_DEFAULT_DEVICE
  double force_limit_n = 0.0;  // a cap below the device's nominal maximum [N]; 0 = that maximum
};

class OpenHapticsDevice final : public Device {
 public:
  // Initialises the device, enables force output and starts the HD scheduler. Errors name the
  // call and the SDK's text, e.g. `openhaptics "Default Device": hdInitDevice: <text> (HD error
  // 0x..., internal N)`.
  static ParseResult<std::unique_ptr<OpenHapticsDevice>> open(const OpenHapticsSettings& settings);
  // The same with default settings for the named device (empty = HD_DEFAULT_DEVICE).
  static ParseResult<std::unique_ptr<OpenHapticsDevice>> open(const std::string& device_name) {
    return open(OpenHapticsSettings{.device_name = device_name});
  }

  // Renders zero force, stops the scheduler and disables the device.
  ~OpenHapticsDevice() override;
  OpenHapticsDevice(const OpenHapticsDevice&) = delete;
  OpenHapticsDevice& operator=(const OpenHapticsDevice&) = delete;

  std::string_view name() const override { return name_; }
  int degrees_of_freedom() const override { return 6; }  // the stylus gimbal; no jaw
  DeviceCapabilities capabilities() const override;

  // One HD frame: reads the pose and buttons, writes the last force set. After a fault the frame
  // still runs (the pose stays live) and the force written is zero.
  DeviceState poll(double t) override;

  // Stores force_n for the next frame, scaled down to max_force_n() if longer; a non-finite
  // force is stored as zero. No SDK call.
  void set_force(const Vec3& force_n) override;

  // "openhaptics: <hdGetErrorString> (HD error 0x..., internal N)" for the first HD error seen
  // during a frame; it latches until the device is reopened.
  std::string_view fault() const override { return fault_; }

  // The force cap applied by set_force() [N].
  double max_force_n() const { return max_force_n_; }

 private:
  OpenHapticsDevice(unsigned int handle, std::string name, double max_force_n);
  void check_errors();

  unsigned int handle_;  // HHD
  std::string name_;
  double max_force_n_;
  std::array<double, 3> force_{};  // [N], written in the next frame
  DeviceState state_;
  std::array<char, 256> fault_text_{};
  std::string_view fault_;
};

}  // namespace incise::devices
