#pragma once
// One fuzz target per file in fuzz/ (docs/fuzzing.md). Each defines LLVMFuzzerTestOneInput and
// calls one boundary where bytes become values, catching only the errors that boundary declares:
// anything else escaping (another exception type, a crash, a sanitizer report, a NaN where the
// contract forbids one) is a finding. `fuzz_check` turns a broken contract into an abort that
// libFuzzer and the corpus runner both report with the input that caused it.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace incise::fuzz {

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

#define fuzz_check(condition)                                                               \
  do {                                                                                      \
    if (!(condition)) {                                                                     \
      std::fprintf(stderr, "%s:%d: contract broken: %s\n", __FILE__, __LINE__, #condition); \
      std::abort();                                                                         \
    }                                                                                       \
  } while (false)

}  // namespace incise::fuzz
