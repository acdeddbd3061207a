// The binary frames of the agent link (devices/protocol.h): DeviceState frames the server decodes
// and ForceModel frames the agent decodes. A rejected frame has a reason that fits a close frame;
// an accepted one encodes back to a frame that decodes to the same message. The first byte picks
// the direction.
#include <array>
#include <span>

#include "devices/protocol.h"
#include "fuzz/fuzz_target.h"
#include "server/wire_text.h"

using namespace incise;

namespace {
template <typename Result>
bool refused_well(const Result& result) {
  if (result) return false;
  fuzz_check(!result.reason().empty());
  fuzz_check(result.reason().size() <= devices::kMaxCloseReasonSize);
  fuzz_check(server::is_valid_utf8(result.reason()));
  return true;
}

// A frame `decode` accepts encodes back (`payload` picks what is encoded) to one that decodes to
// the same message.
template <typename Decode, typename Payload>
void check_round_trip(Decode decode, std::span<const std::uint8_t> frame, Payload payload) {
  const auto result = decode(frame);
  if (refused_well(result)) return;
  const auto& m = result.message();
  std::array<std::uint8_t, 512> out{};
  const auto n = devices::encode(payload(m), m.header.sequence, m.header.timestamp_us, out);
  fuzz_check(n > 0);
  const auto again = decode(std::span<const std::uint8_t>(out.data(), n));
  fuzz_check(again && payload(again.message()) == payload(m) && again.message().header == m.header);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::span<const std::uint8_t> frame(data + 1, size - 1);
  if ((data[0] & 1) == 0) {
    check_round_trip(devices::decode, frame, [](const auto& m) { return m.state; });
  } else {
    check_round_trip(devices::decode_force_model, frame, [](const auto& m) { return m.model; });
  }
  return 0;
}
