// Scene files (sim/io/scene_json.h) and surgical scene files (sim/surgery/scene_file.h, the
// shape only: building the anatomy takes a second): a file either fails with SceneError naming
// the problem or parses. The first byte picks which.
#include "fuzz/fuzz_target.h"
#include "sim/io/json_object_reader.h"
#include "sim/io/scene_json.h"
#include "sim/scene/scene_error.h"
#include "sim/surgery/scene_file.h"

using namespace incise;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const auto text = fuzz::as_text(data + 1, size - 1);
  try {
    if ((data[0] & 1) == 0) {
      sim::parse_scene_text(text);
    } else {
      sim::surgery::parse_surgical_scene_file(sim::parse_json_text(text));
    }
  } catch (const sim::SceneError& e) {
    fuzz_check(e.what()[0] != '\0');
  }
  return 0;
}
