#include "sim/io/json_object_reader.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "sim/scene/scene_error.h"

namespace incise::sim {

using nlohmann::json;

std::string member_path(const std::string& path, std::string_view key) {
  // A key of other characters is quoted as JSON writes it: a NUL or a byte that is not UTF-8
  // must not reach the message (a NUL ended what() there, found by the fuzzing).
  const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-';
  });
  const std::string shown =
      plain ? std::string(key)
            : json(std::string(key)).dump(-1, ' ', false, json::error_handler_t::replace);
  return path.empty() ? shown : path + "." + shown;
}

std::string element_path(const std::string& path, std::size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

std::string describe(const json& value) {
  // dump() escapes control characters, so the result is one line.
  std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
  constexpr std::size_t kMaxLength = 40;
  if (text.size() > kMaxLength) text = text.substr(0, kMaxLength - 3) + "...";
  return text;
}

JsonObjectReader::JsonObjectReader(const json& value, std::string path,
                                   std::initializer_list<std::string_view> allowed)
    : object_(value), path_(std::move(path)) {
  if (!object_.is_object()) {
    throw SceneError(path_, "must be an object (got " + describe(object_) + ")");
  }
  for (const auto& item : object_.items()) {
    if (std::find(allowed.begin(), allowed.end(), item.key()) != allowed.end()) continue;
    std::string expected;
    for (const std::string_view name : allowed) {
      expected += (expected.empty() ? "" : ", ") + std::string(name);
    }
    throw SceneError(member_path(path_, item.key()),
                     "unknown key (expected one of: " + expected + ")");
  }
}

const json& JsonObjectReader::required(std::string_view key) const {
  const auto it = object_.find(key);
  if (it == object_.end()) throw SceneError(path(key), "is required");
  return *it;
}

Real JsonObjectReader::number(std::string_view key) const {
  return read_number(required(key), path(key));
}

std::int64_t JsonObjectReader::integer(std::string_view key) const {
  return read_integer(required(key), path(key));
}

bool JsonObjectReader::boolean(std::string_view key) const {
  const json& value = required(key);
  if (!value.is_boolean()) {
    throw SceneError(path(key), "must be true or false (got " + describe(value) + ")");
  }
  return value.get<bool>();
}

std::string JsonObjectReader::string(std::string_view key) const {
  const json& value = required(key);
  if (!value.is_string()) {
    throw SceneError(path(key), "must be a string (got " + describe(value) + ")");
  }
  return value.get<std::string>();
}

Vec3 JsonObjectReader::vec3(std::string_view key) const {
  return read_vec3(required(key), path(key));
}

Vec3i JsonObjectReader::ivec3(std::string_view key) const {
  const json& value = required(key);
  const std::string at = path(key);
  if (!value.is_array() || value.size() != 3) {
    throw SceneError(at, "must be an array of 3 integers (got " + describe(value) + ")");
  }
  Vec3i result;
  for (std::size_t a = 0; a < 3; ++a) {
    const std::int64_t n = read_integer(value[a], element_path(at, a));
    if (n < std::numeric_limits<int>::min() || n > std::numeric_limits<int>::max()) {
      throw SceneError(element_path(at, a), "is out of range (got " + describe(value[a]) + ")");
    }
    result(static_cast<Eigen::Index>(a)) = static_cast<int>(n);
  }
  return result;
}

Real read_number(const json& value, const std::string& path) {
  if (!value.is_number()) {
    throw SceneError(path, "must be a number (got " + describe(value) + ")");
  }
  const Real number = value.get<Real>();
  if (!std::isfinite(number))
    throw SceneError(path, "must be finite (got " + describe(value) + ")");
  return number;
}

std::int64_t read_integer(const json& value, const std::string& path) {
  if (value.is_number_integer()) {
    if (value.is_number_unsigned() &&
        value.get<std::uint64_t>() >
            static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      throw SceneError(path, "is out of range (got " + describe(value) + ")");
    }
    return value.get<std::int64_t>();
  }
  // 2^62: integral doubles beyond it would not convert exactly, and no count here gets near.
  constexpr Real kLimit = 4611686018427387904.0;
  if (value.is_number_float()) {
    const Real number = value.get<Real>();
    if (std::isfinite(number) && std::floor(number) == number && std::abs(number) < kLimit) {
      return static_cast<std::int64_t>(number);
    }
  }
  throw SceneError(path, "must be an integer (got " + describe(value) + ")");
}

Vec3 read_vec3(const json& value, const std::string& path) {
  if (!value.is_array() || value.size() != 3) {
    throw SceneError(path, "must be an array of 3 numbers (got " + describe(value) + ")");
  }
  Vec3 result;
  for (std::size_t a = 0; a < 3; ++a) {
    result(static_cast<Eigen::Index>(a)) = read_number(value[a], element_path(path, a));
  }
  return result;
}

nlohmann::json parse_json_text(std::string_view text) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    // A syntax error or a number beyond a double's range (out_of_range 406); what() is e.g.
    // "[json.exception.parse_error.101] parse error at line 1, column 2: ...".
    std::string reason = error.what();
    const std::size_t start = reason.find("] ");
    if (start != std::string::npos) reason.erase(0, start + 2);
    throw SceneError("", "malformed JSON: " + reason);
  }
}

std::string read_text_file(const std::filesystem::path& file) {
  std::error_code error;
  if (std::filesystem::is_directory(file, error)) throw SceneError("", "is a directory");
  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw SceneError("", std::string("cannot open file (") + std::strerror(errno) + ")");
  std::ostringstream text;
  text << stream.rdbuf();
  if (stream.bad()) throw SceneError("", "cannot read file");
  return text.str();
}

}  // namespace incise::sim
