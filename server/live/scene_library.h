#pragma once
// The scenes tasks refer to ("scenes/palpation.json"), compiled into the server from sim/scenes/
// so that a deployed server needs no source tree. A scene's version is a hash of its text: a
// recording stores it, and a replay refuses to run against a scene that has changed since.
#include <optional>
#include <string>
#include <string_view>

namespace incise::server::live {

struct SceneSource {
  std::string_view id;    // as tasks name it, e.g. "scenes/palpation.json"
  std::string_view text;  // the JSON
};

// The scene with this id, or nullopt.
std::optional<SceneSource> find_scene(std::string_view id);

// FNV-1a 64 of the text, 16 hex digits.
std::string scene_version(std::string_view text);

}  // namespace incise::server::live
