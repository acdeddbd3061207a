// A station's calibration JSON (devices/station_calibration_json.h), as an admin stores it: what
// parses serialises to JSON that parses to the same calibration.
#include "devices/station_calibration_json.h"
#include "fuzz/fuzz_target.h"

using namespace incise;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto parsed = devices::parse_station_calibration(fuzz::as_text(data, size));
  if (!parsed) {
    fuzz_check(!parsed.error.empty());
    return 0;
  }
  const auto text = devices::station_calibration_json(*parsed.value);
  const auto again = devices::parse_station_calibration(text);
  fuzz_check(again);
  fuzz_check(devices::station_calibration_json(*again.value) == text);
  return 0;
}
