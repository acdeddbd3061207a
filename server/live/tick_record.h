#pragma once
// What a recording stores per simulation tick: the device input the tick used (enough to re-run
// the simulation bit for bit) and the tool force it produced (for the metrics, so that scoring
// need not re-simulate). Chunks of the recording (db recording_chunks.data) are plain arrays of
// fixed-size little-endian records:
//
//   offset size  field
//        0    4  tick          u32: bits 0-28 the tick, counted from 0 at the session start
//                              (paused time is skipped); bits 29-30 the physics' shedding level
//                              the tick ran at (SimEngine::set_shed_level; 0 in recordings made
//                              before shedding existed, which is what they ran at); bit 31 set:
//                              the second hand's record of the same tick (kSecondHandBit | tick),
//                              right after the first hand's
//        4    1  buttons       u8
//        5    4  jaw           f32
//        9   24  position      3 x f64 tool tip [m], scene frame
//       33   32  orientation   4 x f64 unit quaternion w, x, y, z
//       65   12  force         3 x f32 force on the tool [N] after the tick
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "devices/device_state.h"

namespace incise::server::live {

// One hand's input and the force on its tool.
struct HandRecord {
  devices::DeviceState input;
  float force[3] = {0, 0, 0};
};

// A tick of a one- or two-handed session: the first hand (device 0) in input and force, the
// second (device 1) in second when has_second.
struct TickRecord {
  std::uint32_t tick = 0;  // <= kMaxRecordedTick
  std::uint8_t shed = 0;   // 0 .. 3
  devices::DeviceState input;
  float force[3] = {0, 0, 0};
  bool has_second = false;
  HandRecord second;
};

inline constexpr std::size_t kTickRecordSize = 77;
inline constexpr std::uint32_t kSecondHandBit = 0x80000000u;
inline constexpr int kShedShift = 29;
inline constexpr std::uint32_t kShedBits = 0x60000000u;
// The last tick a recording can number: 12 days at 500 Hz.
inline constexpr std::uint32_t kMaxRecordedTick = 0x1fffffffu;

// Appends record's kTickRecordSize bytes to out (twice that with a second hand).
void append_tick_record(const TickRecord& record, std::vector<std::uint8_t>& out);

// Decodes a chunk into out (appending). Returns "" or why the chunk is malformed (its size is
// not a multiple of the record size, a tick does not follow its predecessor, or a second hand's
// record does not follow its tick's first).
std::string decode_tick_records(std::span<const std::uint8_t> chunk, std::vector<TickRecord>& out);

}  // namespace incise::server::live
