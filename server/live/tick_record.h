#pragma once
// What a recording stores per simulation tick: the device input the tick used (enough to re-run
// the simulation bit for bit) and the tool force it produced (for the metrics, so that scoring
// need not re-simulate). Chunks of the recording (db recording_chunks.data) are plain arrays of
// fixed-size little-endian records:
//
//   offset size  field
//        0    4  tick          u32, counted from 0 at the session start (paused time is skipped)
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

struct TickRecord {
  std::uint32_t tick = 0;
  devices::DeviceState input;
  float force[3] = {0, 0, 0};
};

inline constexpr std::size_t kTickRecordSize = 77;

// Appends record's kTickRecordSize bytes to out.
void append_tick_record(const TickRecord& record, std::vector<std::uint8_t>& out);

// Decodes a chunk into out (appending). Returns "" or why the chunk is malformed (its size is
// not a multiple of the record size, or a tick does not follow its predecessor).
std::string decode_tick_records(std::span<const std::uint8_t> chunk, std::vector<TickRecord>& out);

}  // namespace incise::server::live
