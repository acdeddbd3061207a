// The fuzz targets outside a libFuzzer build: runs LLVMFuzzerTestOneInput once on every file
// named on the command line, or in the directories named (the seed corpora of fuzz/corpus/ and
// any crash found since). This is how the README's test command replays every target's corpus
// with the ordinary compiler; deploy/fuzz.sh runs the same targets under libFuzzer.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <vector>

#include "fuzz/fuzz_target.h"

namespace {
int run_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::cerr << "cannot read " << file << "\n";
    return 1;
  }
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                std::istreambuf_iterator<char>());
  LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  int inputs = 0;
  int failures = 0;
  for (int i = 1; i < argc; ++i) {
    const std::filesystem::path path = argv[i];
    if (std::filesystem::is_directory(path)) {
      for (const auto& entry : std::filesystem::recursive_directory_iterator(path)) {
        if (!entry.is_regular_file()) continue;
        failures += run_file(entry.path());
        ++inputs;
      }
    } else {
      failures += run_file(path);
      ++inputs;
    }
  }
  std::cout << argv[0] << ": " << inputs << " inputs ran\n";
  // An empty corpus proves nothing: a renamed folder must fail, not pass silently.
  return failures == 0 && inputs > 0 ? 0 : 1;
}
