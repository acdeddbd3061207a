// Curriculum files (curriculum/curriculum_json.h) as an admin imports them: a file either fails
// with CurriculumError naming the problem, or parses to a curriculum whose JSON parses again.
#include "curriculum/curriculum_error.h"
#include "curriculum/curriculum_json.h"
#include "fuzz/fuzz_target.h"

using namespace incise;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto parsed = curriculum::parse_curriculum_text(fuzz::as_text(data, size));
    // What was stored is exported and imported again by admins: it must read back.
    curriculum::parse_curriculum(curriculum::to_json(parsed));
  } catch (const curriculum::CurriculumError& e) {
    fuzz_check(e.what()[0] != '\0');
  }
  return 0;
}
