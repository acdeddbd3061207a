// The agent's JSON text messages (devices/protocol.h): the hello, the link report and the type
// of any text. A report that parses is re-serialised by the server for the viewers, so it must
// parse again to the same fields.
#include "devices/protocol.h"
#include "fuzz/fuzz_target.h"
#include "server/wire_text.h"

using namespace incise;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto text = fuzz::as_text(data, size);
  devices::message_type(text);
  const auto hello = devices::parse_hello(text);
  if (!hello) fuzz_check(!hello.error.empty());
  const auto report = devices::parse_link_report(text);
  if (!report) {
    fuzz_check(!report.error.empty());
    return 0;
  }
  const auto again = devices::parse_link_report(devices::build_link_report(*report.value));
  fuzz_check(again);
  fuzz_check(devices::build_link_report(*again.value) == devices::build_link_report(*report.value));
  return 0;
}
