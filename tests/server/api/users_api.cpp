// User administration: server/api/users_api.cpp through the router.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "api/api_test_app.h"
#include "db/users_repo.h"

namespace incise::server::test {
namespace {

class UsersApi : public ApiTest {
 protected:
  void SetUp() override {
    ApiTest::SetUp();
    admin_ = session_of(Who::admin);
  }

  Response create(const nlohmann::json& body) { return post("/api/users", body, admin_); }

  std::string admin_;
};

TEST_F(UsersApi, AdminCreatesAUser) {
  const auto audits = count("audit_log");
  const auto response = create({{"username", "new.trainee_1-a"},
                                {"password", "0123456789"},
                                {"role", "trainee"},
                                {"display_name", "New Trainee"}});
  ASSERT_EQ(response.result(), http::status::created) << response.body();
  const auto user = json_of(response);
  EXPECT_EQ(user["username"], "new.trainee_1-a");
  EXPECT_EQ(user["display_name"], "New Trainee");
  EXPECT_EQ(user["role"], "trainee");
  EXPECT_EQ(user["id"], user_id("new.trainee_1-a"));
  EXPECT_EQ(user.size(), 4u) << user;
  EXPECT_EQ(count("audit_log"), audits + 1);
  EXPECT_TRUE(db::UsersRepo(db()).authenticate("new.trainee_1-a", "0123456789"));

  const auto list = json_of(get("/api/users", admin_));
  ASSERT_EQ(list.size(), 4u);
  EXPECT_EQ(list.dump().find("password"), std::string::npos);
}

TEST_F(UsersApi, DisplayNameDefaultsToTheUsername) {
  const auto response =
      create({{"username", "ines2"}, {"password", "0123456789"}, {"role", "instructor"}});
  ASSERT_EQ(response.result(), http::status::created) << response.body();
  EXPECT_EQ(json_of(response)["display_name"], "ines2");
}

TEST_F(UsersApi, DuplicateUsernamesAre409) {
  const auto users = count("users");
  EXPECT_TRUE(
      is_error(create({{"username", "trainee"}, {"password", "0123456789"}, {"role", "admin"}}),
               http::status::conflict, "username 'trainee' is already taken"));
  EXPECT_EQ(count("users"), users);
}

TEST_F(UsersApi, InvalidUsersAre422) {
  const auto users = count("users");
  const std::string name_rule = "username must be 3-32 characters of a-z, 0-9, '.', '_' or '-'";
  for (const std::string& name : std::vector<std::string>{
           "ab", std::string(33, 'a'), "Upper", "with space", "\u00fcmlaut", "semi;colon", ""}) {
    EXPECT_TRUE(
        is_error(create({{"username", name}, {"password", "0123456789"}, {"role", "trainee"}}),
                 http::status::unprocessable_entity, name_rule))
        << name;
  }
  EXPECT_TRUE(
      is_error(create({{"username", "abc"}, {"password", "012345678"}, {"role", "trainee"}}),
               http::status::unprocessable_entity, "password must have at least 10 characters"));
  EXPECT_TRUE(is_error(create({{"username", "abc"}, {"password", "0123456789"}, {"role", "root"}}),
                       http::status::unprocessable_entity,
                       "role must be trainee, instructor or admin (got 'root')"));
  EXPECT_TRUE(is_error(create({{"username", "abc"}, {"password", "0123456789"}}),
                       http::status::unprocessable_entity, "missing field 'role'"));
  EXPECT_TRUE(is_error(
      create(
          {{"username", "abc"}, {"password", "0123456789"}, {"role", "trainee"}, {"admin", true}}),
      http::status::unprocessable_entity, "unknown field 'admin'"));
  EXPECT_TRUE(
      is_error(create({{"username", "abc"}, {"password", 123456789012}, {"role", "trainee"}}),
               http::status::unprocessable_entity, "field 'password' must be a string"));
  EXPECT_EQ(count("users"), users);
}

}  // namespace
}  // namespace incise::server::test
