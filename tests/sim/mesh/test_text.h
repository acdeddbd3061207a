#pragma once

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "sim/mesh/mesh_file_error.h"

namespace incise::sim::test {

// text with its only occurrence of from replaced by to (throws if from is missing or repeated,
// so that a test edits exactly the line it means).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  if (at == std::string::npos || text.find(from, at + 1) != std::string::npos) {
    throw std::logic_error("replaced: '" + from + "' is not in the text exactly once");
  }
  return text.replace(at, from.size(), to);
}

// text up to and including line `lines` (1-based).
inline std::string first_lines(const std::string& text, int lines) {
  std::size_t end = 0;
  for (int i = 0; i < lines; ++i)
    end = text.find('\n', end) + 1;
  return text.substr(0, end);
}

// Runs read and checks that it throws MeshFileError at line with exactly the problem.
template <typename Read>
::testing::AssertionResult throws_at(Read read, int line, const std::string& problem) {
  try {
    read();
  } catch (const MeshFileError& error) {
    if (error.line() == line && error.problem() == problem) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "got line " << error.line() << ": " << error.problem()
                                         << "\nwanted line " << line << ": " << problem;
  }
  return ::testing::AssertionFailure() << "no MeshFileError";
}

}  // namespace incise::sim::test
