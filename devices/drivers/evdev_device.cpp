#include "devices/drivers/evdev_device.h"

#include <fcntl.h>
#include <linux/input.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace incise::devices {
namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();
constexpr int kAxisCount = 6;  // ABS_X .. ABS_RZ and REL_X .. REL_RZ are codes 0 .. 5
static_assert(ABS_X == 0 && ABS_RZ == 5 && REL_X == 0 && REL_RZ == 5);

// Bitmaps as the EVIOCGBIT ioctls fill them: arrays of unsigned long, bit i of word i / bits.
constexpr int kBitsPerLong = 8 * sizeof(unsigned long);
template <int Bits>
using BitArray = std::array<unsigned long, (Bits + kBitsPerLong - 1) / kBitsPerLong>;

template <std::size_t N>
bool test_bit(const std::array<unsigned long, N>& bits, int bit) {
  return (bits[bit / kBitsPerLong] >> (bit % kBitsPerLong)) & 1ul;
}

// DeviceState::buttons bit for an EV_KEY code, or -1 for keys we ignore.
int button_bit(unsigned code) {
  if (code >= BTN_0 && code <= BTN_7) return static_cast<int>(code - BTN_0);
  if (code >= BTN_LEFT && code <= BTN_TASK) return static_cast<int>(code - BTN_LEFT);
  return -1;
}

// Joysticks and gamepads have ABS_X .. ABS_RZ too, but their sticks and triggers rest off-centre.
template <std::size_t N>
bool is_joystick_or_gamepad(const std::array<unsigned long, N>& keys) {
  return test_bit(keys, BTN_TRIGGER) || test_bit(keys, BTN_SOUTH);
}

bool finite_positive(double x) {
  return std::isfinite(x) && x > 0.0;
}

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

// exp(omega dt / 2) * q: q turned by |omega| dt about omega's direction, station frame.
Quat rotated(const Quat& q, const std::array<double, 3>& omega, double dt) {
  const double rate = std::sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
  if (rate == 0.0 || dt <= 0.0) return q;
  const double half = 0.5 * rate * dt;
  const double s = std::sin(half) / rate;
  const Quat d{std::cos(half), s * omega[0], s * omega[1], s * omega[2]};
  Quat r{
      d.w * q.w - d.x * q.x - d.y * q.y - d.z * q.z, d.w * q.x + d.x * q.w + d.y * q.z - d.z * q.y,
      d.w * q.y - d.x * q.z + d.y * q.w + d.z * q.x, d.w * q.z + d.x * q.y - d.y * q.x + d.z * q.w};
  const double norm = std::sqrt(r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z);
  r.w /= norm;
  r.x /= norm;
  r.y /= norm;
  r.z /= norm;
  return r;
}

}  // namespace

std::string check_evdev_settings(const EvdevSettings& s) {
  if (!finite_positive(s.max_speed_m_s)) {
    return "max_speed_m_s: must be finite and > 0, got " + number(s.max_speed_m_s);
  }
  if (!finite_positive(s.max_rate_rad_s)) {
    return "max_rate_rad_s: must be finite and > 0, got " + number(s.max_rate_rad_s);
  }
  if (!std::isfinite(s.full_scale) || s.full_scale < 0.0) {
    return "full_scale: must be finite and >= 0 (0 = automatic), got " + number(s.full_scale);
  }
  if (!(s.deadzone >= 0.0 && s.deadzone < 1.0)) {
    return "deadzone: " + number(s.deadzone) + " not in [0, 1)";
  }
  if (!finite_positive(s.relative_hold_s)) {
    return "relative_hold_s: must be finite and > 0, got " + number(s.relative_hold_s);
  }
  for (std::size_t i = 0; i < s.axis_sign.size(); ++i) {
    if (s.axis_sign[i] != 1 && s.axis_sign[i] != -1) {
      return "axis_sign[" + std::to_string(i) + "]: must be 1 or -1, got " +
             std::to_string(s.axis_sign[i]);
    }
  }
  const double lo[3] = {s.workspace_min.x, s.workspace_min.y, s.workspace_min.z};
  const double hi[3] = {s.workspace_max.x, s.workspace_max.y, s.workspace_max.z};
  const double start[3] = {s.start_position.x, s.start_position.y, s.start_position.z};
  const char* axis = "xyz";
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(lo[i]) || !std::isfinite(hi[i]) || !(lo[i] < hi[i])) {
      return std::string("workspace: min.") + axis[i] + " " + number(lo[i]) + " must be < max." +
             axis[i] + " " + number(hi[i]) + " (both finite)";
    }
    if (!(start[i] >= lo[i] && start[i] <= hi[i])) {
      return std::string("start_position.") + axis[i] + ": " + number(start[i]) + " outside [" +
             number(lo[i]) + ", " + number(hi[i]) + "]";
    }
  }
  return {};
}

EvdevDevice::EvdevDevice(int fd, EvdevSettings settings, std::string name)
    : fd_(fd), settings_(settings), name_(std::move(name)) {
  if (std::string error = check_evdev_settings(settings_); !error.empty()) {
    ::close(fd_);
    throw std::invalid_argument("evdev settings: " + error);
  }
  const double scale = settings_.full_scale > 0.0 ? settings_.full_scale : kSpaceMouseFullScale;
  centre_.fill(0.0);
  half_range_.fill(scale);
  expires_.fill(kNever);
  state_.position = settings_.start_position;
  state_.jaw = settings_.button0_toggles_jaw ? 1.0f : 0.0f;
}

EvdevDevice::~EvdevDevice() {
  if (fd_ >= 0) ::close(fd_);
}

ParseResult<std::unique_ptr<EvdevDevice>> EvdevDevice::open(const std::string& path,
                                                            EvdevSettings settings) {
  using Result = ParseResult<std::unique_ptr<EvdevDevice>>;
  if (std::string error = check_evdev_settings(settings); !error.empty()) {
    return Result::failure("evdev settings: " + error);
  }
  if (path.empty()) {
    // The first readable 3D mouse; if there are only unreadable ones, say so, since the fix
    // (a udev rule) differs from having none.
    std::string unreadable;
    for (const EvdevCandidate& candidate : find_3d_mice()) {
      if (candidate.readable) return open(candidate.path, settings);
      unreadable += (unreadable.empty() ? "" : ", ") + candidate.path + " (" + candidate.name + ")";
    }
    if (!unreadable.empty()) {
      return Result::failure("evdev: no readable 3D mouse; found " + unreadable +
                             " without read permission (see docs/device_drivers.md, udev rule)");
    }
    return Result::failure("evdev: no 3D mouse found under /dev/input");
  }
  const std::string where = "evdev " + path + ": ";
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return Result::failure(where + std::strerror(errno));
  auto fail = [&](const std::string& why) {
    ::close(fd);
    return Result::failure(where + why);
  };

  BitArray<EV_MAX + 1> types{};
  BitArray<ABS_MAX + 1> abs{};
  BitArray<REL_MAX + 1> rel{};
  BitArray<KEY_MAX + 1> keys{};
  if (::ioctl(fd, EVIOCGBIT(0, sizeof types), types.data()) < 0) {
    return fail(std::string("not an input event device (EVIOCGBIT: ") + std::strerror(errno) + ")");
  }
  if (test_bit(types, EV_ABS)) ::ioctl(fd, EVIOCGBIT(EV_ABS, sizeof abs), abs.data());
  if (test_bit(types, EV_REL)) ::ioctl(fd, EVIOCGBIT(EV_REL, sizeof rel), rel.data());
  if (test_bit(types, EV_KEY)) ::ioctl(fd, EVIOCGBIT(EV_KEY, sizeof keys), keys.data());
  bool six_abs = true;
  bool six_rel = true;
  for (int i = 0; i < kAxisCount; ++i) {
    six_abs = six_abs && test_bit(abs, i);
    six_rel = six_rel && test_bit(rel, i);
  }
  if (!six_abs && !six_rel) return fail("has no 6-axis input (not a 3D mouse?)");
  if (is_joystick_or_gamepad(keys)) return fail("is a joystick or gamepad, not a 3D mouse");

  // Absolute axes: their range, and where the cap is now (no event comes until it moves).
  std::array<input_absinfo, kAxisCount> info{};
  if (six_abs) {
    for (int i = 0; i < kAxisCount; ++i) {
      if (::ioctl(fd, EVIOCGABS(i), &info[i]) < 0) {
        return fail("EVIOCGABS(" + std::to_string(i) + "): " + std::strerror(errno));
      }
      if (info[i].maximum <= info[i].minimum) {
        return fail("axis " + std::to_string(i) + " reports an empty range [" +
                    std::to_string(info[i].minimum) + ", " + std::to_string(info[i].maximum) + "]");
      }
    }
  }

  char device_name[128] = "unnamed";
  if (::ioctl(fd, EVIOCGNAME(sizeof device_name), device_name) < 0) {
    std::strcpy(device_name, "unnamed");
  }
  device_name[sizeof device_name - 1] = '\0';
  const bool auto_scale = settings.full_scale == 0.0;
  auto device =
      std::make_unique<EvdevDevice>(fd, settings, "evdev " + path + " (" + device_name + ")");
  device->can_query_ = true;
  device->button_count_ = 0;
  for (unsigned code = 0; code <= KEY_MAX; ++code) {
    const int bit = button_bit(code);
    if (bit >= 0 && test_bit(keys, static_cast<int>(code))) {
      device->button_count_ = std::max(device->button_count_, bit + 1);
    }
  }
  if (six_abs) {
    for (int i = 0; i < kAxisCount; ++i) {
      if (auto_scale) {
        device->centre_[i] = 0.5 * (info[i].minimum + static_cast<double>(info[i].maximum));
        device->half_range_[i] = 0.5 * (info[i].maximum - static_cast<double>(info[i].minimum));
      }
      device->axes_.value[i] = info[i].value;
      device->pending_axes_.value[i] = info[i].value;
    }
  } else {
    device->axes_.relative.fill(true);
  }
  return Result::success(std::move(device));
}

DeviceCapabilities EvdevDevice::capabilities() const {
  return {.has_force_output = false,
          .has_jaw = settings_.button0_toggles_jaw,
          .button_count = button_count_};
}

DeviceState EvdevDevice::poll(double t) {
  static_assert(sizeof(input_event) <= 24, "bytes_ holds kEventBufferSize events");
  constexpr std::size_t kEventSize = sizeof(input_event);
  for (int reads = 0; fault_.empty() && reads < kMaxReadsPerPoll; ++reads) {
    const std::size_t space = bytes_.size() - pending_bytes_;
    const ssize_t n = ::read(fd_, bytes_.data() + pending_bytes_, space);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) break;
      set_fault(errno == ENODEV ? "device unplugged" : "read failed", errno == ENODEV ? 0 : errno);
      break;
    }
    if (n == 0) {
      set_fault("end of input", 0);
      break;
    }
    const std::size_t total = pending_bytes_ + static_cast<std::size_t>(n);
    const std::size_t whole = total / kEventSize;
    for (std::size_t k = 0; k < whole; ++k) {
      input_event event;
      std::memcpy(&event, bytes_.data() + k * kEventSize, kEventSize);
      apply_event(event.type, event.code, event.value, t);
    }
    pending_bytes_ = total - whole * kEventSize;
    std::memmove(bytes_.data(), bytes_.data() + whole * kEventSize, pending_bytes_);
    if (static_cast<std::size_t>(n) < space) break;  // drained
  }
  // A fault freezes the pose where the last good poll left it.
  if (fault_.empty() && has_time_ && t > last_t_) integrate(last_t_, t);
  if (!has_time_ || t > last_t_) last_t_ = t;
  has_time_ = true;
  return state_;
}

void EvdevDevice::apply_event(unsigned type, unsigned code, int value, double t) {
  if (dropping_) {
    // The kernel's buffer overflowed: the frame in flight is incomplete (evdev's SYN_DROPPED
    // contract), so skip to the next SYN_REPORT and read the device's state afresh.
    if (type == EV_SYN && code == SYN_REPORT) {
      dropping_ = false;
      resynchronise();
    }
    return;
  }
  switch (type) {
    case EV_SYN:
      if (code == SYN_REPORT) commit_frame(t);
      if (code == SYN_DROPPED) {
        dropping_ = true;
        touched_ = 0;
        pending_buttons_ = state_.buttons;
      }
      break;
    case EV_ABS:
    case EV_REL:
      if (code < kAxisCount) {
        pending_axes_.value[code] = value;
        pending_axes_.relative[code] = type == EV_REL;
        touched_ |= 1u << code;
      }
      break;
    case EV_KEY:
      if (const int bit = button_bit(code); bit >= 0) {
        const auto mask = static_cast<uint8_t>(1u << bit);
        pending_buttons_ = value != 0 ? (pending_buttons_ | mask) : (pending_buttons_ & ~mask);
      }
      break;
    default:
      break;
  }
}

void EvdevDevice::commit_frame(double t) {
  for (int i = 0; i < kAxisCount; ++i) {
    if (!(touched_ & (1u << i))) continue;
    axes_.value[i] = pending_axes_.value[i];
    axes_.relative[i] = pending_axes_.relative[i];
    expires_[i] = axes_.relative[i] ? t + settings_.relative_hold_s : kNever;
  }
  touched_ = 0;
  set_buttons(pending_buttons_);
}

void EvdevDevice::set_buttons(uint8_t buttons) {
  const bool pressed0 = (buttons & 1u) && !(state_.buttons & 1u);
  if (settings_.button0_toggles_jaw && pressed0) state_.jaw = state_.jaw > 0.5f ? 0.0f : 1.0f;
  state_.buttons = buttons;
  pending_buttons_ = buttons;
}

void EvdevDevice::resynchronise() {
  for (int i = 0; i < kAxisCount; ++i) {
    input_absinfo info{};
    // A relative axis has no state to ask for; 0 stops the tool, the safe guess.
    const bool known = can_query_ && !axes_.relative[i] && ::ioctl(fd_, EVIOCGABS(i), &info) == 0;
    axes_.value[i] = known ? info.value : centre_[i];
    pending_axes_.value[i] = axes_.value[i];
    expires_[i] = kNever;
  }
  BitArray<KEY_MAX + 1> keys{};
  if (can_query_ && ::ioctl(fd_, EVIOCGKEY(sizeof keys), keys.data()) >= 0) {
    uint8_t buttons = 0;
    for (unsigned code = BTN_0; code <= BTN_TASK; ++code) {
      const int bit = button_bit(code);
      if (bit >= 0 && test_bit(keys, static_cast<int>(code))) buttons |= 1u << bit;
    }
    set_buttons(buttons);
  }
}

double EvdevDevice::normalised(int axis, double value) const {
  const double n = std::clamp((value - centre_[axis]) / half_range_[axis], -1.0, 1.0);
  return std::abs(n) < settings_.deadzone ? 0.0 : n;
}

void EvdevDevice::integrate(double t0, double t1) {
  // An axis moves the tool over (t0, min(t1, expires)]; absolute axes never expire.
  std::array<double, kAxisCount> n{};
  for (int i = 0; i < kAxisCount; ++i) {
    n[i] = settings_.axis_sign[i] * normalised(i, axes_.value[i]);
  }
  double* position[3] = {&state_.position.x, &state_.position.y, &state_.position.z};
  const double lo[3] = {settings_.workspace_min.x, settings_.workspace_min.y,
                        settings_.workspace_min.z};
  const double hi[3] = {settings_.workspace_max.x, settings_.workspace_max.y,
                        settings_.workspace_max.z};
  for (int i = 0; i < 3; ++i) {
    const double active = std::min(t1, expires_[i]) - t0;
    if (active > 0.0) *position[i] += settings_.max_speed_m_s * n[i] * active;
    *position[i] = std::clamp(*position[i], lo[i], hi[i]);
  }

  // The angular velocity is piecewise constant between the rotation axes' expiry times (empty
  // segments are harmless).
  std::array<double, 5> cuts{t0, std::clamp(expires_[3], t0, t1), std::clamp(expires_[4], t0, t1),
                             std::clamp(expires_[5], t0, t1), t1};
  if (cuts[1] > cuts[2]) std::swap(cuts[1], cuts[2]);
  if (cuts[2] > cuts[3]) std::swap(cuts[2], cuts[3]);
  if (cuts[1] > cuts[2]) std::swap(cuts[1], cuts[2]);
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double a = cuts[k];
    const double b = cuts[k + 1];
    std::array<double, 3> omega{};
    for (int j = 0; j < 3; ++j) {
      if (expires_[3 + j] >= b) omega[j] = settings_.max_rate_rad_s * n[3 + j];
    }
    state_.orientation = rotated(state_.orientation, omega, b - a);
  }
}

void EvdevDevice::set_fault(const char* what, int error_number) {
  if (error_number != 0) {
    std::snprintf(fault_text_.data(), fault_text_.size(), "%s: %s: %s", name_.c_str(), what,
                  std::strerror(error_number));
  } else {
    std::snprintf(fault_text_.data(), fault_text_.size(), "%s: %s", name_.c_str(), what);
  }
  fault_ = fault_text_.data();
}

bool capability_bit(std::string_view bitmap, int bit) {
  // Words are separated by spaces and written most significant first; walk from the end.
  constexpr int kWordBits = 8 * sizeof(unsigned long);  // the kernel prints unsigned longs
  int word_index = 0;
  std::size_t end = bitmap.size();
  while (end > 0 && (bitmap[end - 1] == ' ' || bitmap[end - 1] == '\n'))
    --end;
  while (end > 0) {
    std::size_t begin = bitmap.find_last_of(' ', end - 1);
    begin = begin == std::string_view::npos ? 0 : begin + 1;
    if (word_index == bit / kWordBits) {
      unsigned long long word = 0;
      const char* first = bitmap.data() + begin;
      const char* last = bitmap.data() + end;
      const auto [ptr, ec] = std::from_chars(first, last, word, 16);
      if (ec != std::errc{} || ptr != last) return false;
      return (word >> (bit % kWordBits)) & 1ull;
    }
    ++word_index;
    end = begin;
    while (end > 0 && bitmap[end - 1] == ' ')
      --end;
  }
  return false;
}

std::vector<EvdevCandidate> find_3d_mice(const std::filesystem::path& sysfs_input,
                                         const std::filesystem::path& dev_input) {
  auto read_line = [](const std::filesystem::path& file) {
    std::ifstream in(file);
    std::string line;
    std::getline(in, line);
    return line;
  };
  std::vector<EvdevCandidate> found;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(sysfs_input, ec)) {
    const std::string node = entry.path().filename().string();
    if (!node.starts_with("event")) continue;
    const std::filesystem::path device = entry.path() / "device";
    const std::string abs = read_line(device / "capabilities" / "abs");
    const std::string rel = read_line(device / "capabilities" / "rel");
    const std::string key = read_line(device / "capabilities" / "key");
    bool six_abs = true;
    bool six_rel = true;
    for (int i = 0; i < kAxisCount; ++i) {
      six_abs = six_abs && capability_bit(abs, i);
      six_rel = six_rel && capability_bit(rel, i);
    }
    if (!six_abs && !six_rel) continue;
    if (capability_bit(key, BTN_TRIGGER) || capability_bit(key, BTN_SOUTH)) continue;
    EvdevCandidate candidate;
    candidate.path = (dev_input / node).string();
    candidate.name = read_line(device / "name");
    candidate.relative_axes = !six_abs;
    candidate.readable = ::access(candidate.path.c_str(), R_OK) == 0;
    found.push_back(std::move(candidate));
  }
  std::sort(found.begin(), found.end(),
            [](const EvdevCandidate& a, const EvdevCandidate& b) { return a.path < b.path; });
  return found;
}

}  // namespace incise::devices
