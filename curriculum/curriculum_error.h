#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace incise::curriculum {

// A curriculum definition is malformed. path locates the offending value the way the JSON
// spells it, e.g. "modules[0].tasks[1].metrics[0].threshold.op" ("" for the whole document);
// what() is "<path>: <reason>", with "(root)" for the empty path, so that an admin editing the
// file can find the value at once.
class CurriculumError : public std::runtime_error {
 public:
  CurriculumError(std::string path, std::string reason)
      : std::runtime_error((path.empty() ? "(root)" : path) + ": " + reason),
        path_(std::move(path)),
        reason_(std::move(reason)) {}

  const std::string& path() const { return path_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string path_;
  std::string reason_;
};

}  // namespace incise::curriculum
