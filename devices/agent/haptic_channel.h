#pragma once
// What the haptic thread and the io thread share, all lock-free: device states one way, the
// latest force model the other, and whether a server link is up.

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "devices/agent/seqlock.h"
#include "devices/agent/spsc_ring.h"
#include "devices/device_state.h"
#include "devices/protocol.h"
#include "devices/workspace_mapping.h"

namespace incise::devices::agent {

// A station has up to two devices (two hands), indexed 0 and 1 on the wire.
inline constexpr std::size_t kMaxDevices = 2;

// A device state and its sample time [us since the agent's epoch]: the frame's timestamp_us.
// The haptic loop queues one per device at the send rate; send is false for a state the deadband
// held back (the hand has not moved): the io thread then only records it locally, if asked to.
struct TimedState {
  DeviceState state;
  uint64_t timestamp_us = 0;
  bool send = true;
};

// What the haptic loop reports about one device, for the link report and the logs. Written by
// the haptic thread, read by any (relaxed atomics: each value stands alone).
struct DeviceTelemetry {
  std::atomic<uint32_t> model_age_us{0};  // of the model rendered on the last tick
  // io thread -> haptic thread: the round trip of the latest state the server answered for the
  // first time [us]; 0 until one is known.
  std::atomic<uint32_t> round_trip_us{0};
  std::atomic<uint8_t> fault{0};           // GuardFault of the last tick
  std::atomic<float> force_n{0.0f};        // |commanded force| on the last tick
  std::atomic<float> damping{0.0f};        // injected by the passivity guard [N s/m]
  std::atomic<float> dissipated_j{0.0f};   // by the passivity guard since the start [J]
  std::atomic<uint64_t> fault_ticks{0};    // ticks the watchdog had the force off
  std::atomic<uint64_t> states_held{0};    // states the deadband held back
  std::atomic<uint64_t> states_queued{0};  // states queued to send
};

// A force model and when it arrived, on the agent's steady clock.
struct ReceivedModel {
  ForceModel model;
  std::chrono::steady_clock::time_point received_at;
};

// 512 states: a quarter of a second for two devices at the highest send rate, far longer than
// one write.
inline constexpr std::size_t kStateRingCapacity = 512;

struct HapticChannel {
  SpscRing<TimedState, kStateRingCapacity> states;         // haptic thread -> io thread
  std::array<Seqlock<ReceivedModel>, kMaxDevices> models;  // io thread -> haptic thread
  // The station's calibration, io thread -> haptic thread: device frame -> scene frame.
  std::array<Seqlock<WorkspaceMapping>, kMaxDevices> mappings;
  std::array<DeviceTelemetry, kMaxDevices> telemetry;  // haptic thread -> anyone
  std::atomic<uint64_t> loop_ticks{0};                 // ticks run: the link report's loop rate
  // Set by the io thread once the server has welcomed us, cleared when the link ends. While it
  // is clear no states are queued and no force is rendered.
  std::atomic<bool> link_up{false};
};

}  // namespace incise::devices::agent
