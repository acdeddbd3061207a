// The fuzz targets outside a libFuzzer build.
//
//   fuzz_<target> PATH...                    runs LLVMFuzzerTestOneInput once on every file named,
//                                            or in the directories named (fuzz/corpus/<target>/)
//   fuzz_<target> --mutate S [--seed N] PATH...   then, for S seconds, on random mutations of them
//
// The corpus run is how the README's test command replays every target's seeds and past crashes
// with the ordinary compiler. The mutation run is the test command's short fuzzing, on the
// sanitized copies (asan/fuzz_<target>_mutations): blind mutations of the seeds (bit flips,
// hostile tokens such as 1e400 or a 0xFF byte, erased, repeated and spliced ranges), without
// libFuzzer's coverage feedback; deploy/fuzz.sh runs the same targets under libFuzzer for real.
// An input that fails is written to crash-fuzz_<target>[_asan]-<seed>-<n> (a corpus input:
// crash-...-corpus-<i>) in the working directory and printed, escaped, to stderr, so that a CI log
// alone reproduces it.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz/fuzz_target.h"

// Present only in a sanitized program: called when a sanitizer report ends it.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace {

using Bytes = std::vector<std::uint8_t>;

// What the failure handlers write: set before every run, read only by the handlers.
Bytes g_current;
char g_crash_path[256] = "";
volatile std::sig_atomic_t g_reported = 0;

void write_all(int fd, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t written = ::write(fd, bytes, size);
    if (written <= 0) return;
    bytes += written;
    size -= static_cast<std::size_t>(written);
  }
}

// Async-signal-safe: open, write and close only, on buffers prepared before the run.
void report_current_input() {
  if (g_reported != 0 || g_crash_path[0] == '\0') return;
  g_reported = 1;
  const int fd = ::open(g_crash_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    write_all(fd, g_current.data(), g_current.size());
    ::close(fd);
  }
  static const char kHead[] = "\nfuzz: the failing input is in ";
  write_all(STDERR_FILENO, kHead, sizeof kHead - 1);
  write_all(STDERR_FILENO, g_crash_path, std::strlen(g_crash_path));
  static const char kEscaped[] = "; escaped (at most 4096 bytes):\n";
  write_all(STDERR_FILENO, kEscaped, sizeof kEscaped - 1);
  static const char kHex[] = "0123456789abcdef";
  const std::size_t shown = g_current.size() < 4096 ? g_current.size() : 4096;
  for (std::size_t i = 0; i < shown; ++i) {
    const std::uint8_t byte = g_current[i];
    if (byte >= 0x20 && byte < 0x7f && byte != '\\') {
      write_all(STDERR_FILENO, &byte, 1);
    } else {
      const char escaped[4] = {'\\', 'x', kHex[byte >> 4], kHex[byte & 15]};
      write_all(STDERR_FILENO, escaped, 4);
    }
  }
  write_all(STDERR_FILENO, "\n", 1);
}

void on_fatal_signal(int signal_number) {
  report_current_input();
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

Bytes read_file(const std::filesystem::path& file, bool& ok) {
  std::ifstream in(file, std::ios::binary);
  ok = static_cast<bool>(in);
  return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void run(const Bytes& input) {
  LLVMFuzzerTestOneInput(input.data(), input.size());
}

// Values that have broken parsers before, or that sit on a boundary of a number or an encoding.
constexpr std::string_view kTokens[] = {"1e400",
                                        "-1e400",
                                        "1e-400",
                                        "-0",
                                        "NaN",
                                        "Infinity",
                                        "18446744073709551615",
                                        "9223372036854775808",
                                        "-9223372036854775809",
                                        "4294967296",
                                        "-1",
                                        "0",
                                        "null",
                                        "true",
                                        "\"\"",
                                        "{}",
                                        "[]",
                                        "\xff",
                                        "\xc0\x80",
                                        "\xed\xa0\x80",
                                        "\xe2\x80\xae",
                                        "\\u0000",
                                        "\\ud800",
                                        "%00",
                                        "%ff",
                                        "\r\n",
                                        "\r\n\r\n",
                                        "\n",
                                        "\t",
                                        "..",
                                        "/../",
                                        ",",
                                        ":",
                                        "\"",
                                        "\\",
                                        "{",
                                        "}",
                                        "[",
                                        "]",
                                        "$Format",
                                        "Content-Length: 99999999999\r\n",
                                        "Transfer-Encoding: chunked\r\n"};
constexpr std::uint8_t kBytes[] = {0x00, 0x01, 0x7f, 0x80, 0xff, '"', '\\', '{', '}', '[', ']',
                                   ',',  ':',  '\n', '\r', ' ',  '0', '9',  '-', '.', 'e'};
constexpr std::size_t kMaxSize = 1 << 16;

// One to four stacked mutations of a corpus input (another one for splicing).
Bytes mutate(const Bytes& input, const Bytes& other, std::mt19937_64& random) {
  Bytes out = input;
  auto pick = [&random](std::size_t n) {  // uniform in [0, n), n > 0
    return std::uniform_int_distribution<std::size_t>(0, n - 1)(random);
  };
  const std::size_t count = 1 + pick(4);
  for (std::size_t m = 0; m < count; ++m) {
    const std::size_t at = pick(out.size() + 1);  // a position, the end included
    switch (pick(7)) {
      case 0:  // flip a bit
        if (!out.empty()) out[pick(out.size())] ^= static_cast<std::uint8_t>(1u << pick(8));
        break;
      case 1:  // a byte that means something to a parser
        if (!out.empty()) out[pick(out.size())] = kBytes[pick(std::size(kBytes))];
        break;
      case 2: {  // erase a range
        const std::size_t length = std::min(out.size() - at, 1 + pick(16));
        out.erase(out.begin() + static_cast<std::ptrdiff_t>(at),
                  out.begin() + static_cast<std::ptrdiff_t>(at + length));
        break;
      }
      case 3: {  // repeat a range of the input at another place
        if (out.empty()) break;
        const std::size_t from = pick(out.size());
        const std::size_t length = std::min(out.size() - from, 1 + pick(64));
        const Bytes range(out.begin() + static_cast<std::ptrdiff_t>(from),
                          out.begin() + static_cast<std::ptrdiff_t>(from + length));
        out.insert(out.begin() + static_cast<std::ptrdiff_t>(std::min(at, out.size())),
                   range.begin(), range.end());
        break;
      }
      case 4: {  // insert a hostile token
        const std::string_view token = kTokens[pick(std::size(kTokens))];
        out.insert(out.begin() + static_cast<std::ptrdiff_t>(at), token.begin(), token.end());
        break;
      }
      case 5: {  // overwrite with a hostile token
        const std::string_view token = kTokens[pick(std::size(kTokens))];
        for (std::size_t i = 0; i < token.size() && at + i < out.size(); ++i) {
          out[at + i] = static_cast<std::uint8_t>(token[i]);
        }
        break;
      }
      default: {  // this input's head, the other's tail
        const std::size_t tail = pick(other.size() + 1);
        out.resize(at);
        out.insert(out.end(), other.begin() + static_cast<std::ptrdiff_t>(tail), other.end());
        break;
      }
    }
    if (out.size() > kMaxSize) out.resize(kMaxSize);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string name = std::filesystem::path(argv[0]).filename().string();
  double mutate_seconds = 0;
  std::uint64_t seed =
      static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
  std::vector<std::filesystem::path> paths;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    try {
      if (arg == "--mutate" && i + 1 < argc) {
        mutate_seconds = std::stod(argv[++i]);
      } else if (arg == "--seed" && i + 1 < argc) {
        seed = std::stoull(argv[++i]);
      } else {
        paths.emplace_back(arg);
      }
    } catch (const std::exception&) {
      std::cerr << name << ": " << arg << " needs a number\n";
      return 2;
    }
  }

  std::vector<Bytes> corpus;
  int failures = 0;
  for (const auto& path : paths) {
    std::vector<std::filesystem::path> files;
    if (std::filesystem::is_directory(path)) {
      for (const auto& entry : std::filesystem::recursive_directory_iterator(path)) {
        if (entry.is_regular_file()) files.push_back(entry.path());
      }
    } else {
      files.push_back(path);
    }
    std::sort(files.begin(), files.end());  // a seed gives the same inputs on any file system
    for (const auto& file : files) {
      bool ok = false;
      corpus.push_back(read_file(file, ok));
      if (!ok) {
        std::cerr << "cannot read " << file << "\n";
        ++failures;
      }
    }
  }

  // A sanitizer report ends the program through its death callback; a broken contract through
  // abort(), which no sanitizer catches. In a plain build the other fatal signals are ours too;
  // in a sanitized one they are left to the sanitizer, whose report names the bad access.
  if (__sanitizer_set_death_callback) {
    __sanitizer_set_death_callback(report_current_input);
    std::signal(SIGABRT, on_fatal_signal);
  } else {
    for (int signal_number : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) {
      std::signal(signal_number, on_fatal_signal);
    }
  }
  for (std::size_t i = 0; i < corpus.size(); ++i) {
    g_current = corpus[i];
    std::snprintf(g_crash_path, sizeof g_crash_path, "crash-%s-corpus-%zu", name.c_str(), i);
    run(g_current);
  }
  g_crash_path[0] = '\0';  // a leak found at exit is no one input's
  std::cout << name << ": " << corpus.size() << " inputs ran\n";
  // An empty corpus proves nothing: a renamed folder must fail, not pass silently.
  if (failures != 0 || corpus.empty()) return 1;

  if (mutate_seconds > 0) {
    std::mt19937_64 random(seed);
    const auto end =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(mutate_seconds);
    std::uint64_t executions = 0;
    std::uniform_int_distribution<std::size_t> which(0, corpus.size() - 1);
    while (std::chrono::steady_clock::now() < end) {
      for (int batch = 0; batch < 64; ++batch, ++executions) {
        const Bytes& base = corpus[which(random)];
        const Bytes& other = corpus[which(random)];
        g_current = mutate(base, other, random);
        std::snprintf(g_crash_path, sizeof g_crash_path, "crash-%s-%llu-%llu", name.c_str(),
                      static_cast<unsigned long long>(seed),
                      static_cast<unsigned long long>(executions));
        run(g_current);
      }
    }
    g_crash_path[0] = '\0';
    std::cout << name << ": " << executions << " mutations of them ran in " << mutate_seconds
              << " s (seed " << seed << ")\n";
  }
  return 0;
}
