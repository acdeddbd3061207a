#include "server/api/request_fields.h"

#include <algorithm>
#include <cstdint>

#include "db/password.h"
#include "server/api/api_error.h"
#include "server/wire_text.h"

namespace incise::server {

using boost::beast::http::status;

RequestFields::RequestFields(const nlohmann::json& body,
                             std::initializer_list<std::string_view> allowed)
    : body_(body) {
  if (!body.is_object()) throw ApiError(status::unprocessable_entity, "body must be a JSON object");
  for (const auto& [key, _] : body.items()) {
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      throw ApiError(status::unprocessable_entity, "unknown field '" + key + "'");
    }
  }
}

const nlohmann::json& RequestFields::required(std::string_view key) const {
  const auto it = body_.find(key);
  if (it == body_.end() || it->is_null()) {
    throw ApiError(status::unprocessable_entity, "missing field '" + std::string(key) + "'");
  }
  return *it;
}

std::string RequestFields::string(std::string_view key) const {
  const auto& value = required(key);
  if (!value.is_string()) {
    throw ApiError(status::unprocessable_entity,
                   "field '" + std::string(key) + "' must be a string");
  }
  return value.get<std::string>();
}

std::string RequestFields::string_or(std::string_view key, std::string fallback) const {
  if (!body_.contains(key) || body_.at(key).is_null()) return fallback;
  return string(key);
}

std::string RequestFields::text(std::string_view key, bool multiline) const {
  auto value = string(key);
  if (!is_plain_text(value, multiline)) {
    throw ApiError(status::unprocessable_entity,
                   "field '" + std::string(key) +
                       "' must not contain control characters or text-direction overrides");
  }
  return value;
}

std::string RequestFields::text_or(std::string_view key, std::string fallback,
                                   bool multiline) const {
  if (!body_.contains(key) || body_.at(key).is_null()) return fallback;
  return text(key, multiline);
}

std::int64_t RequestFields::integer(std::string_view key) const {
  const auto& value = required(key);
  if (!value.is_number_integer()) {
    throw ApiError(status::unprocessable_entity,
                   "field '" + std::string(key) + "' must be an integer");
  }
  // nlohmann keeps 2^63..2^64-1 as unsigned; get<int64_t> would wrap them to negatives.
  if (value.is_number_unsigned() &&
      value.get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX)) {
    throw ApiError(status::unprocessable_entity,
                   "field '" + std::string(key) + "' is out of range (at most 2^63 - 1)");
  }
  return value.get<std::int64_t>();
}

double RequestFields::number(std::string_view key) const {
  const auto& value = required(key);
  if (!value.is_number()) {
    throw ApiError(status::unprocessable_entity,
                   "field '" + std::string(key) + "' must be a number");
  }
  return value.get<double>();
}

bool RequestFields::boolean(std::string_view key) const {
  const auto& value = required(key);
  if (!value.is_boolean()) {
    throw ApiError(status::unprocessable_entity,
                   "field '" + std::string(key) + "' must be true or false");
  }
  return value.get<bool>();
}

void check_new_password(std::string_view field, const std::string& password,
                        std::string_view username) {
  if (const auto problem = db::password_problem(password, username); !problem.empty())
    throw ApiError(status::unprocessable_entity, std::string(field) + " " + problem);
}

bool RequestFields::has(std::string_view key) const {
  return body_.contains(key);
}

}  // namespace incise::server
