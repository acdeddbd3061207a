#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace incise::sim {

// A scene cannot be simulated as given. path locates the offending value the way the scene's JSON
// form spells it, e.g. "material.E" or "constraints[1].where.box" ("" for the scene as a whole);
// what() is "<path>: <reason>", or just the reason for the empty path.
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string path, std::string reason)
      : std::runtime_error(path.empty() ? reason : path + ": " + reason),
        path_(std::move(path)),
        reason_(std::move(reason)) {}

  const std::string& path() const { return path_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string path_;
  std::string reason_;
};

}  // namespace incise::sim
