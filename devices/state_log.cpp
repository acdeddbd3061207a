#include "devices/state_log.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

namespace incise::devices {

ParseResult<std::unique_ptr<StateLogWriter>> StateLogWriter::create(const std::string& path) {
  using Result = ParseResult<std::unique_ptr<StateLogWriter>>;
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr)
    return Result::failure("record-states " + path + ": " + std::strerror(errno));
  return Result::success(std::unique_ptr<StateLogWriter>(new StateLogWriter(file)));
}

StateLogWriter::~StateLogWriter() {
  std::fclose(file_);
}

bool StateLogWriter::write(const DeviceState& state, uint64_t timestamp_us) {
  if (failed_) return false;
  std::array<uint8_t, kDeviceStateFrameSize> frame;
  const std::size_t size = encode(state, sequence_, timestamp_us, frame);
  failed_ = std::fwrite(frame.data(), 1, size, file_) != size;
  if (!failed_) ++sequence_;
  return !failed_;
}

ParseResult<std::vector<TimedSample>> read_state_log(const std::string& path) {
  using Result = ParseResult<std::vector<TimedSample>>;
  const std::string where = "replay " + path + ": ";
  std::ifstream file(path, std::ios::binary);
  if (!file) return Result::failure(where + "cannot open");
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)),
                                   std::istreambuf_iterator<char>());
  if (bytes.empty()) return Result::failure(where + "empty");
  if (bytes.size() % kDeviceStateFrameSize != 0) {
    return Result::failure(where + std::to_string(bytes.size()) +
                           " bytes is not a whole number of " +
                           std::to_string(kDeviceStateFrameSize) + "-byte frames");
  }
  std::vector<TimedSample> samples;
  std::array<uint64_t, kMaxStationDevices> last{};
  for (std::size_t at = 0, n = 0; at < bytes.size(); at += kDeviceStateFrameSize, ++n) {
    const DecodeResult result =
        decode(std::span<const uint8_t>(bytes.data() + at, kDeviceStateFrameSize));
    const std::string frame = where + "frame " + std::to_string(n) + ": ";
    if (!result) return Result::failure(frame + std::string(result.reason()));
    const DeviceStateMessage& message = result.message();
    uint64_t& previous = last[message.state.device_index];
    if (message.header.timestamp_us < previous) {
      return Result::failure(frame + "timestamp " + std::to_string(message.header.timestamp_us) +
                             " us goes back (previous " + std::to_string(previous) + " us)");
    }
    previous = message.header.timestamp_us;
    samples.push_back({message.header.timestamp_us, message.state});
  }
  return Result::success(std::move(samples));
}

ReplayDevice::ReplayDevice(std::vector<TimedSample> samples, bool loop, std::string name)
    : samples_(std::move(samples)), loop_(loop), name_(std::move(name)) {}

ParseResult<std::unique_ptr<Device>> ReplayDevice::open(const std::string& argument) {
  using Result = ParseResult<std::unique_ptr<Device>>;
  std::string path = argument;
  int index = 0;
  bool loop = true;
  // Options after the path, comma separated.
  for (auto comma = path.rfind(','); comma != std::string::npos; comma = path.rfind(',')) {
    const std::string option = path.substr(comma + 1);
    if (option == "once") {
      loop = false;
    } else if (option == "device=0" || option == "device=1") {
      index = option.back() - '0';
    } else {
      return Result::failure("replay " + argument + ": unknown option '" + option +
                             "' (device=0, device=1 or once)");
    }
    path.resize(comma);
  }
  if (path.empty()) return Result::failure("replay: needs a file, replay:FILE[,device=N][,once]");
  auto log = read_state_log(path);
  if (!log) return Result::failure(log.error);
  std::vector<TimedSample> mine;
  for (const TimedSample& sample : *log.value)
    if (sample.state.device_index == index) mine.push_back(sample);
  if (mine.empty()) {
    return Result::failure("replay " + path + ": no states of device " + std::to_string(index));
  }
  const std::string name = "replay (" + path + ", device " + std::to_string(index) + ")";
  return Result::success(std::make_unique<ReplayDevice>(std::move(mine), loop, name));
}

DeviceState ReplayDevice::poll(double t) {
  const uint64_t first = samples_.front().timestamp_us;
  const uint64_t span = samples_.back().timestamp_us - first;
  auto offset = static_cast<uint64_t>(std::llround(std::max(t, 0.0) * 1e6));
  // A loop lasts the span plus one mean sample interval, so the last sample is held as long as
  // the others before the first comes again.
  const uint64_t interval = samples_.size() > 1 ? span / (samples_.size() - 1) : 0;
  if (loop_ && span > 0) offset %= span + interval;
  const uint64_t at = first + offset;
  // The last sample at or before `at`.
  const auto after = std::upper_bound(
      samples_.begin(), samples_.end(), at,
      [](uint64_t value, const TimedSample& sample) { return value < sample.timestamp_us; });
  DeviceState state = (after == samples_.begin() ? samples_.front() : *(after - 1)).state;
  state.device_index = 0;  // the haptic loop numbers the station's devices itself
  return state;
}

}  // namespace incise::devices
