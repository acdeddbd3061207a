#pragma once
// Device-state logs: what `incise-agent --record-states FILE` writes and the replay driver plays.
// A log is a plain sequence of DeviceState protocol frames (protocol.h, kDeviceStateFrameSize
// bytes each: the header's timestamp_us is the sample time, its sequence counts from 0), so the
// one decoder validates both the wire and the files.

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "devices/device.h"
#include "devices/parse_result.h"
#include "devices/protocol.h"

namespace incise::devices {

struct TimedSample {
  uint64_t timestamp_us = 0;
  DeviceState state;
};

// Appends frames to a file; not for the haptic thread (it writes through stdio).
class StateLogWriter {
 public:
  // Errors read `record-states FILE: <strerror>`.
  static ParseResult<std::unique_ptr<StateLogWriter>> create(const std::string& path);
  ~StateLogWriter();
  StateLogWriter(const StateLogWriter&) = delete;
  StateLogWriter& operator=(const StateLogWriter&) = delete;
  // Returns false once a write failed (disk full); later calls do nothing.
  bool write(const DeviceState& state, uint64_t timestamp_us);
  uint64_t written() const { return sequence_; }

 private:
  explicit StateLogWriter(std::FILE* file) : file_(file) {}
  std::FILE* file_;
  uint32_t sequence_ = 0;
  bool failed_ = false;
};

// Reads a whole log: every frame must decode, and timestamps must not decrease per device.
// Errors read `replay FILE: frame 12: jaw 1.5 outside [0, 1]`.
ParseResult<std::vector<TimedSample>> read_state_log(const std::string& path);

// Plays one device's samples of a log in time, sample and hold: poll(t) gives the last sample at
// or before the first sample's time + t (looping after the last if loop).
class ReplayDevice final : public Device {
 public:
  // samples: one device's, non-decreasing timestamps, at least one.
  ReplayDevice(std::vector<TimedSample> samples, bool loop, std::string name);
  // argument "FILE[,device=N][,once]": the log's device N (default 0), looping unless once.
  static ParseResult<std::unique_ptr<Device>> open(const std::string& argument);

  std::string_view name() const override { return name_; }
  int degrees_of_freedom() const override { return 7; }
  DeviceCapabilities capabilities() const override { return {.has_jaw = true, .button_count = 8}; }
  DeviceState poll(double t) override;

 private:
  std::vector<TimedSample> samples_;
  bool loop_;
  std::string name_;
};

}  // namespace incise::devices
