#include "server/live/tick_record.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <iterator>

namespace incise::server::live {
namespace {

static_assert(std::endian::native == std::endian::little,
              "recordings are little-endian; add byte swapping for a big-endian host");

template <class T>
void put(std::vector<std::uint8_t>& out, T value) {
  const auto at = out.size();
  out.resize(at + sizeof(T));
  std::memcpy(out.data() + at, &value, sizeof(T));
}

template <class T>
T get(const std::uint8_t*& p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  p += sizeof(T);
  return value;
}

void append_hand(std::uint32_t tick, const devices::DeviceState& s, const float (&force)[3],
                 std::vector<std::uint8_t>& out) {
  put(out, tick);
  put(out, s.buttons);
  put(out, s.jaw);
  put(out, s.position.x);
  put(out, s.position.y);
  put(out, s.position.z);
  put(out, s.orientation.w);
  put(out, s.orientation.x);
  put(out, s.orientation.y);
  put(out, s.orientation.z);
  for (float f : force)
    put(out, f);
}

}  // namespace

void append_tick_record(const TickRecord& record, std::vector<std::uint8_t>& out) {
  const std::uint32_t shed = static_cast<std::uint32_t>(record.shed) << kShedShift & kShedBits;
  append_hand((record.tick & kMaxRecordedTick) | shed, record.input, record.force, out);
  if (record.has_second) {
    append_hand(record.tick | kSecondHandBit, record.second.input, record.second.force, out);
  }
}

std::string decode_tick_records(std::span<const std::uint8_t> chunk, std::vector<TickRecord>& out) {
  if (chunk.size() % kTickRecordSize != 0) {
    return "chunk of " + std::to_string(chunk.size()) + " bytes is not a whole number of " +
           std::to_string(kTickRecordSize) + "-byte tick records";
  }
  const std::uint8_t* p = chunk.data();
  const std::uint8_t* end = p + chunk.size();
  while (p != end) {
    const std::uint32_t tick = get<std::uint32_t>(p);
    HandRecord hand;
    hand.input.buttons = get<std::uint8_t>(p);
    hand.input.jaw = get<float>(p);
    hand.input.position = {get<double>(p), get<double>(p), get<double>(p)};
    hand.input.orientation = {get<double>(p), get<double>(p), get<double>(p), get<double>(p)};
    for (float& f : hand.force)
      f = get<float>(p);
    if ((tick & kSecondHandBit) != 0) {
      const std::uint32_t of = tick & ~kSecondHandBit;
      if (out.empty() || out.back().tick != of || out.back().has_second) {
        return "a second hand's record for tick " + std::to_string(of) +
               " does not follow that tick's first";
      }
      hand.input.device_index = 1;
      out.back().has_second = true;
      out.back().second = hand;
      continue;
    }
    // Every tick of a recording has the same hands: a two-handed tick after a one-handed one
    // (or the reverse) is a corrupt chunk.
    if (out.size() >= 2 && out[out.size() - 1].has_second != out[out.size() - 2].has_second) {
      return "tick " + std::to_string(out.back().tick) + " has " +
             (out.back().has_second ? "two hands" : "one hand") + ", tick " +
             std::to_string(out[out.size() - 2].tick) + " had " +
             (out[out.size() - 2].has_second ? "two" : "one");
    }
    TickRecord r;
    r.tick = tick & kMaxRecordedTick;
    r.shed = static_cast<std::uint8_t>((tick & kShedBits) >> kShedShift);
    r.input = hand.input;
    std::copy(std::begin(hand.force), std::end(hand.force), std::begin(r.force));
    if (!out.empty() && r.tick != out.back().tick + 1) {
      return "tick " + std::to_string(r.tick) + " follows tick " + std::to_string(out.back().tick);
    }
    out.push_back(r);
  }
  if (out.size() >= 2 && out[out.size() - 1].has_second != out[out.size() - 2].has_second) {
    return "tick " + std::to_string(out.back().tick) + " has " +
           (out.back().has_second ? "two hands" : "one hand") + ", tick " +
           std::to_string(out[out.size() - 2].tick) + " had " +
           (out[out.size() - 2].has_second ? "two" : "one");
  }
  return "";
}

}  // namespace incise::server::live
