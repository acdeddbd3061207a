#pragma once
// What the haptic thread and the io thread share, all lock-free: device states one way, the
// latest force model the other, and whether a server link is up.

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "devices/agent/seqlock.h"
#include "devices/agent/spsc_ring.h"
#include "devices/device_state.h"
#include "devices/protocol.h"

namespace incise::devices::agent {

// A device state and its sample time [us since the agent's epoch]: the frame's timestamp_us.
struct TimedState {
  DeviceState state;
  uint64_t timestamp_us = 0;
};

// A force model and when it arrived, on the agent's steady clock.
struct ReceivedModel {
  ForceModel model;
  std::chrono::steady_clock::time_point received_at;
};

// 256 states: a quarter of a second at the highest send rate, far longer than one write.
inline constexpr std::size_t kStateRingCapacity = 256;

struct HapticChannel {
  SpscRing<TimedState, kStateRingCapacity> states;  // haptic thread -> io thread
  Seqlock<ReceivedModel> model;                     // io thread -> haptic thread
  // Set by the io thread once the server has welcomed us, cleared when the link ends. While it
  // is clear no states are queued and no force is rendered.
  std::atomic<bool> link_up{false};
};

}  // namespace incise::devices::agent
