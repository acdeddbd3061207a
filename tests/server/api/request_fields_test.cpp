// Field-by-field reading of JSON bodies: server/api/request_fields.h.
#include "server/api/request_fields.h"

#include <gtest/gtest.h>

#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "server/api/api_error.h"

namespace incise::server {
namespace {

using nlohmann::json;

// Runs `f` and expects it to throw ApiError 422 with exactly `message`.
void expect_422(const std::function<void()>& f, const std::string& message) {
  try {
    f();
    ADD_FAILURE() << "no ApiError; expected '" << message << "'";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status(), boost::beast::http::status::unprocessable_entity) << e.what();
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(RequestFields, ReadsTypedFields) {
  const json body = {{"name", "Station 2"}, {"count", 42}, {"big", 9007199254740993}};
  const RequestFields fields(body, {"name", "count", "big", "location"});
  EXPECT_EQ(fields.string("name"), "Station 2");
  EXPECT_EQ(fields.integer("count"), 42);
  EXPECT_EQ(fields.integer("big"), 9007199254740993);
  EXPECT_EQ(fields.string_or("location", "nowhere"), "nowhere");
}

TEST(RequestFields, NullCountsAsAbsent) {
  const json body = {{"location", nullptr}, {"name", nullptr}};
  const RequestFields fields(body, {"name", "location"});
  EXPECT_EQ(fields.string_or("location", "fallback"), "fallback");
  expect_422([&] { fields.string("name"); }, "missing field 'name'");
}

TEST(RequestFields, UnknownFieldsAreRefused) {
  expect_422(
      [] {
        RequestFields(json{{"username", "a"}, {"pasword", "b"}}, {"username", "password"});
      },
      "unknown field 'pasword'");
  expect_422([] { RequestFields(json{{"x", 1}}, {}); }, "unknown field 'x'");
}

TEST(RequestFields, TheBodyMustBeAnObject) {
  for (const json& body : {json::array({1, 2}), json("text"), json(3), json(nullptr), json(true)}) {
    expect_422([&] { RequestFields(body, {"a"}); }, "body must be a JSON object");
  }
}

TEST(RequestFields, MissingFields) {
  const json body = json::object();
  const RequestFields fields(body, {"name", "count"});
  expect_422([&] { fields.string("name"); }, "missing field 'name'");
  expect_422([&] { fields.integer("count"); }, "missing field 'count'");
}

TEST(RequestFields, WrongTypes) {
  const json body = {{"s_num", 5},      {"s_bool", true},        {"s_obj", json::object()},
                     {"i_text", "5"},   {"i_real", 1.5},         {"i_whole_real", 2.0},
                     {"i_bool", false}, {"i_arr", json::array()}};
  const RequestFields fields(
      body, {"s_num", "s_bool", "s_obj", "i_text", "i_real", "i_whole_real", "i_bool", "i_arr"});
  for (const char* key : {"s_num", "s_bool", "s_obj"}) {
    expect_422([&] { fields.string(key); }, "field '" + std::string(key) + "' must be a string");
    expect_422([&] { fields.string_or(key, ""); },
               "field '" + std::string(key) + "' must be a string");
  }
  for (const char* key : {"i_text", "i_real", "i_whole_real", "i_bool", "i_arr"}) {
    expect_422([&] { fields.integer(key); }, "field '" + std::string(key) + "' must be an integer");
  }
}

}  // namespace
}  // namespace incise::server
