#pragma once
// Reads a JSON request body field by field with precise 422 errors: every field is named, its
// type checked, and unknown fields refused (a typo should not be silently ignored).
#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace incise::server {

// 422 "<field> must have at least 10 characters" (and so on) unless db::password_problem accepts
// the password for the user `username`.
void check_new_password(std::string_view field, const std::string& password,
                        std::string_view username);

class RequestFields {
 public:
  // Throws ApiError 422 unless `body` is an object whose keys are all in `allowed`.
  RequestFields(const nlohmann::json& body, std::initializer_list<std::string_view> allowed);

  std::string string(std::string_view key) const;
  std::string string_or(std::string_view key, std::string fallback) const;
  // A string to show people (a name, a note): 422 when it holds control characters or direction
  // overrides (server/wire_text.h is_plain_text; `multiline` lets a note break lines).
  std::string text(std::string_view key, bool multiline = false) const;
  std::string text_or(std::string_view key, std::string fallback, bool multiline = false) const;
  std::int64_t integer(std::string_view key) const;
  double number(std::string_view key) const;  // any JSON number
  bool boolean(std::string_view key) const;
  // Whether the body holds the field (for PATCH bodies, where every field is optional).
  bool has(std::string_view key) const;
  // The field's JSON as sent, for shapes the readers above do not cover (e.g. an array); 422
  // when it is missing.
  const nlohmann::json& required(std::string_view key) const;

 private:
  const nlohmann::json& body_;
};

}  // namespace incise::server
