#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace incise::sim {

// The one error of the mesh readers and writers: a file that cannot be opened, read or written,
// or whose content is malformed. what() is "FILE:LINE: problem" (or "FILE: problem" when no line
// applies, e.g. a missing file), so that a command line can print it as it is.
class MeshFileError : public std::runtime_error {
 public:
  //   file     the file as the caller named it
  //   line     1-based line number of the offending text, or 0 for none
  //   problem  what is wrong, e.g. "truncated file: expected 12 nodes, found 9"
  MeshFileError(std::string file, int line, std::string problem)
      : std::runtime_error(message(file, line, problem)),
        file_(std::move(file)),
        line_(line),
        problem_(std::move(problem)) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& problem() const { return problem_; }

 private:
  // Built with append: GCC 12 warns (-Wrestrict, falsely) on the chain of operator+.
  static std::string message(const std::string& file, int line, const std::string& problem) {
    std::string text = file;
    if (line > 0) text.append(":").append(std::to_string(line));
    text.append(": ").append(problem);
    return text;
  }

  std::string file_;
  int line_;
  std::string problem_;
};

}  // namespace incise::sim
