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
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::span<const std::uint8_t> frame(data + 1, size - 1);
  std::array<std::uint8_t, 512> out{};
  if ((data[0] & 1) == 0) {
    const auto result = devices::decode(frame);
    if (refused_well(result)) return 0;
    const auto& m = result.message();
    const auto n = devices::encode(m.state, m.header.sequence, m.header.timestamp_us, out);
    fuzz_check(n > 0);
    const auto again = devices::decode(std::span<const std::uint8_t>(out.data(), n));
    fuzz_check(again && again.message().state == m.state && again.message().header == m.header);
  } else {
    const auto result = devices::decode_force_model(frame);
    if (refused_well(result)) return 0;
    const auto& m = result.message();
    const auto n = devices::encode(m.model, m.header.sequence, m.header.timestamp_us, out);
    fuzz_check(n > 0);
    const auto again = devices::decode_force_model(std::span<const std::uint8_t>(out.data(), n));
    fuzz_check(again && again.message().model == m.model && again.message().header == m.header);
  }
  return 0;
}
