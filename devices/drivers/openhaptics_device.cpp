// The OpenHaptics HD driver; the API it builds against is listed in openhaptics_device.h.

#include "devices/drivers/openhaptics_device.h"

#include <HD/hd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <type_traits>
#include <utility>

namespace incise::devices {
namespace {

static_assert(std::is_same_v<HHD, unsigned int>, "the header stores HHD as unsigned int");

constexpr double kMetresPerMillimetre = 1e-3;
constexpr int kMaxErrorsPerFrame = 8;  // hdGetError() pops a stack; bound the draining

// "<text> (HD error 0x..., internal N)" into out; no allocation.
void describe(const HDErrorInfo& error, char* out, std::size_t size, const char* prefix) {
  const char* text = hdGetErrorString(error.errorCode);
  std::snprintf(out, size, "%s%s (HD error 0x%x, internal %d)", prefix,
                text != nullptr ? text : "unknown error", static_cast<unsigned>(error.errorCode),
                error.internalErrorCode);
}

// The unit quaternion of the rotation block of a column-major 4x4 matrix (R(r, c) = m[4c + r]),
// by Shepperd's method: divide by the largest of the four candidates for accuracy.
Quat quaternion_from_transform(const std::array<double, 16>& m) {
  auto r = [&m](int row, int col) { return m[4 * col + row]; };
  const double trace = r(0, 0) + r(1, 1) + r(2, 2);
  Quat q;
  if (trace > 0.0) {
    const double s = 2.0 * std::sqrt(trace + 1.0);
    q = {0.25 * s, (r(2, 1) - r(1, 2)) / s, (r(0, 2) - r(2, 0)) / s, (r(1, 0) - r(0, 1)) / s};
  } else if (r(0, 0) > r(1, 1) && r(0, 0) > r(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + r(0, 0) - r(1, 1) - r(2, 2));
    q = {(r(2, 1) - r(1, 2)) / s, 0.25 * s, (r(0, 1) + r(1, 0)) / s, (r(0, 2) + r(2, 0)) / s};
  } else if (r(1, 1) > r(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + r(1, 1) - r(0, 0) - r(2, 2));
    q = {(r(0, 2) - r(2, 0)) / s, (r(0, 1) + r(1, 0)) / s, 0.25 * s, (r(1, 2) + r(2, 1)) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + r(2, 2) - r(0, 0) - r(1, 1));
    q = {(r(1, 0) - r(0, 1)) / s, (r(0, 2) + r(2, 0)) / s, (r(1, 2) + r(2, 1)) / s, 0.25 * s};
  }
  // The SDK's matrix is orthonormal to float precision only; the wire protocol wants |q| = 1.
  const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!(norm > 0.0) || !std::isfinite(norm)) return Quat{};
  return {q.w / norm, q.x / norm, q.y / norm, q.z / norm};
}

}  // namespace

ParseResult<std::unique_ptr<OpenHapticsDevice>> OpenHapticsDevice::open(
    const OpenHapticsSettings& settings) {
  using Result = ParseResult<std::unique_ptr<OpenHapticsDevice>>;
  if (!std::isfinite(settings.force_limit_n) || settings.force_limit_n < 0.0) {
    char text[96];
    std::snprintf(text, sizeof text,
                  "openhaptics settings: force_limit_n: must be finite and >= 0, got %g",
                  settings.force_limit_n);
    return Result::failure(text);
  }
  const std::string shown =
      settings.device_name.empty() ? "default device" : "\"" + settings.device_name + "\"";
  const std::string where = "openhaptics " + shown + ": ";
  auto sdk_failure = [&](const char* call, const HDErrorInfo& error) {
    char text[256];
    describe(error, text, sizeof text, "");
    return Result::failure(where + call + ": " + text);
  };

  const HHD handle =
      hdInitDevice(settings.device_name.empty() ? HD_DEFAULT_DEVICE : settings.device_name.c_str());
  if (HDErrorInfo error = hdGetError(); HD_DEVICE_ERROR(error)) {
    return sdk_failure("hdInitDevice", error);
  }
  hdEnable(HD_FORCE_OUTPUT);
  HDdouble nominal = 0.0;
  hdGetDoublev(HD_NOMINAL_MAX_FORCE, &nominal);
  if (HDErrorInfo error = hdGetError(); HD_DEVICE_ERROR(error)) {
    hdDisableDevice(handle);
    return sdk_failure("hdEnable(HD_FORCE_OUTPUT) / HD_NOMINAL_MAX_FORCE", error);
  }
  if (!std::isfinite(nominal) || nominal <= 0.0) {
    hdDisableDevice(handle);
    char text[96];
    std::snprintf(text, sizeof text, "HD_NOMINAL_MAX_FORCE is %g N, expected > 0", nominal);
    return Result::failure(where + text);
  }
  hdStartScheduler();
  if (HDErrorInfo error = hdGetError(); HD_DEVICE_ERROR(error)) {
    hdDisableDevice(handle);
    return sdk_failure("hdStartScheduler", error);
  }
  const double cap =
      settings.force_limit_n > 0.0 ? std::min(settings.force_limit_n, nominal) : nominal;
  return Result::success(std::unique_ptr<OpenHapticsDevice>(
      new OpenHapticsDevice(handle, "openhaptics " + shown, cap)));
}

OpenHapticsDevice::OpenHapticsDevice(unsigned int handle, std::string name, double max_force_n)
    : handle_(handle), name_(std::move(name)), max_force_n_(max_force_n) {}

OpenHapticsDevice::~OpenHapticsDevice() {
  // Leave the motors unpowered before the scheduler that drives them stops.
  const HDdouble zero[3] = {0.0, 0.0, 0.0};
  hdBeginFrame(handle_);
  hdSetDoublev(HD_CURRENT_FORCE, zero);
  hdEndFrame(handle_);
  hdStopScheduler();
  hdDisableDevice(handle_);
}

DeviceCapabilities OpenHapticsDevice::capabilities() const {
  // Touch and Phantom styli have two buttons.
  return {.has_force_output = true, .has_jaw = false, .button_count = 2};
}

DeviceState OpenHapticsDevice::poll(double /*t*/) {
  HDdouble position_mm[3] = {0.0, 0.0, 0.0};
  std::array<HDdouble, 16> transform{};
  HDint buttons = 0;
  const HDdouble zero[3] = {0.0, 0.0, 0.0};

  hdBeginFrame(handle_);
  hdGetDoublev(HD_CURRENT_POSITION, position_mm);
  hdGetDoublev(HD_CURRENT_TRANSFORM, transform.data());
  hdGetIntegerv(HD_CURRENT_BUTTONS, &buttons);
  hdSetDoublev(HD_CURRENT_FORCE, fault_.empty() ? force_.data() : zero);
  hdEndFrame(handle_);
  check_errors();

  state_.position = {position_mm[0] * kMetresPerMillimetre, position_mm[1] * kMetresPerMillimetre,
                     position_mm[2] * kMetresPerMillimetre};
  state_.orientation = quaternion_from_transform(transform);
  state_.buttons = static_cast<uint8_t>(buttons & 0xff);
  return state_;
}

void OpenHapticsDevice::set_force(const Vec3& force_n) {
  const double length =
      std::sqrt(force_n.x * force_n.x + force_n.y * force_n.y + force_n.z * force_n.z);
  if (!std::isfinite(length)) {
    force_ = {0.0, 0.0, 0.0};
    return;
  }
  // Scaling the whole vector keeps the force's direction, unlike clamping each component.
  const double scale = length > max_force_n_ ? max_force_n_ / length : 1.0;
  force_ = {force_n.x * scale, force_n.y * scale, force_n.z * scale};
}

void OpenHapticsDevice::check_errors() {
  for (int k = 0; k < kMaxErrorsPerFrame; ++k) {
    const HDErrorInfo error = hdGetError();
    if (!HD_DEVICE_ERROR(error)) return;
    if (fault_.empty()) {
      describe(error, fault_text_.data(), fault_text_.size(), "openhaptics: ");
      fault_ = fault_text_.data();
      force_ = {0.0, 0.0, 0.0};
    }
  }
}

}  // namespace incise::devices
