#pragma once

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "sim/core/types.h"

namespace incise::sim {

// The JSON path of a member or element: member("material", "E") == "material.E",
// element("loads", 0) == "loads[0]". A key of other than letters, digits, '_' and '-' is quoted and
// escaped as JSON writes it (member("", "a b") == "\"a b\""), so that a message never carries a
// NUL, a control character or a byte that is not UTF-8.
std::string member_path(const std::string& path, std::string_view key);
std::string element_path(const std::string& path, std::size_t index);

// A short one-line rendering of a JSON value for "(got ...)" in messages.
std::string describe(const nlohmann::json& value);

// The JSON value of text; throws SceneError("", "malformed JSON: <parser's reason>").
nlohmann::json parse_json_text(std::string_view text);

// The whole file as text; throws SceneError("", ...) for a directory or a file that cannot be
// opened or read (the caller names the file).
std::string read_text_file(const std::filesystem::path& file);

// Reads one JSON object of a scene: rejects members outside the allowed set and reads typed
// members, throwing SceneError at the member's path ("material.E: must be a number (got
// \"x\")"). Booleans are not numbers; integers may be written as integral floats (1e4).
class JsonObjectReader {
 public:
  // Throws SceneError if value is not an object or has a member outside allowed.
  JsonObjectReader(const nlohmann::json& value, std::string path,
                   std::initializer_list<std::string_view> allowed);

  const std::string& path() const { return path_; }
  std::string path(std::string_view key) const { return member_path(path_, key); }
  bool has(std::string_view key) const { return object_.contains(key); }

  // The member; throws SceneError "is required" if absent.
  const nlohmann::json& required(std::string_view key) const;

  Real number(std::string_view key) const;
  std::int64_t integer(std::string_view key) const;
  std::string string(std::string_view key) const;
  bool boolean(std::string_view key) const;  // true or false, nothing else
  Vec3 vec3(std::string_view key) const;
  Vec3i ivec3(std::string_view key) const;

 private:
  const nlohmann::json& object_;
  std::string path_;
};

// The same checks for a value that is not an object member (e.g. an array element).
Real read_number(const nlohmann::json& value, const std::string& path);
std::int64_t read_integer(const nlohmann::json& value, const std::string& path);
Vec3 read_vec3(const nlohmann::json& value, const std::string& path);

}  // namespace incise::sim
