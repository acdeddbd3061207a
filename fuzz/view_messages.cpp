// A viewer's text messages on the live and replay WebSockets (server/view_message.h). The first
// byte chooses live or replay and how many frames were sent; a refusal's reason is a close
// reason, so it must be valid UTF-8 of at most 123 bytes.
#include "fuzz/fuzz_target.h"
#include "server/view_message.h"
#include "server/wire_text.h"

using namespace incise;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool replay = (data[0] & 1) != 0;
  const std::int64_t frames = data[0] >> 1;
  const auto result = server::parse_view_message(fuzz::as_text(data + 1, size - 1), frames, replay);
  if (result.message) return 0;
  fuzz_check(!result.error.empty());
  fuzz_check(result.error.size() <= 123);
  fuzz_check(server::is_valid_utf8(result.error));
  return 0;
}
