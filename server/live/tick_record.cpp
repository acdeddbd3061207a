#include "server/live/tick_record.h"

#include <bit>
#include <cstring>

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

}  // namespace

void append_tick_record(const TickRecord& record, std::vector<std::uint8_t>& out) {
  const auto& s = record.input;
  put(out, record.tick);
  put(out, s.buttons);
  put(out, s.jaw);
  put(out, s.position.x);
  put(out, s.position.y);
  put(out, s.position.z);
  put(out, s.orientation.w);
  put(out, s.orientation.x);
  put(out, s.orientation.y);
  put(out, s.orientation.z);
  for (float f : record.force)
    put(out, f);
}

std::string decode_tick_records(std::span<const std::uint8_t> chunk, std::vector<TickRecord>& out) {
  if (chunk.size() % kTickRecordSize != 0) {
    return "chunk of " + std::to_string(chunk.size()) + " bytes is not a whole number of " +
           std::to_string(kTickRecordSize) + "-byte tick records";
  }
  const std::uint8_t* p = chunk.data();
  const std::uint8_t* end = p + chunk.size();
  while (p != end) {
    TickRecord r;
    r.tick = get<std::uint32_t>(p);
    r.input.buttons = get<std::uint8_t>(p);
    r.input.jaw = get<float>(p);
    r.input.position = {get<double>(p), get<double>(p), get<double>(p)};
    r.input.orientation = {get<double>(p), get<double>(p), get<double>(p), get<double>(p)};
    for (float& f : r.force)
      f = get<float>(p);
    if (!out.empty() && r.tick != out.back().tick + 1) {
      return "tick " + std::to_string(r.tick) + " follows tick " + std::to_string(out.back().tick);
    }
    out.push_back(r);
  }
  return "";
}

}  // namespace incise::server::live
