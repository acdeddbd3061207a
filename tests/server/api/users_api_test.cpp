// User administration: server/api/users_api.cpp through the router.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "api_test_app.h"
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
                                {"password", "kestrel-0942"},
                                {"role", "trainee"},
                                {"display_name", "New Trainee"}});
  ASSERT_EQ(response.result(), http::status::created) << response.body();
  const auto user = json_of(response);
  EXPECT_EQ(user["username"], "new.trainee_1-a");
  EXPECT_EQ(user["display_name"], "New Trainee");
  EXPECT_EQ(user["role"], "trainee");
  EXPECT_EQ(user["id"], user_id("new.trainee_1-a"));
  EXPECT_EQ(user["instructor_ids"], nlohmann::json::array());  // nobody teaches them yet
  EXPECT_EQ(user["disabled"], false);
  EXPECT_EQ(user["must_change_password"], false);
  EXPECT_EQ(user.size(), 7u) << user;
  EXPECT_EQ(count("audit_log"), audits + 1);
  EXPECT_TRUE(db::UsersRepo(db()).authenticate("new.trainee_1-a", "kestrel-0942"));

  const auto list = json_of(get("/api/users", admin_));
  ASSERT_EQ(list.size(), 5u);  // the four demo logins and this one
  EXPECT_EQ(list.dump().find("password_hash"), std::string::npos);
  EXPECT_EQ(list.dump().find("kestrel-0942"), std::string::npos);
}

TEST_F(UsersApi, DisplayNameDefaultsToTheUsername) {
  const auto response =
      create({{"username", "ines2"}, {"password", "kestrel-0942"}, {"role", "instructor"}});
  ASSERT_EQ(response.result(), http::status::created) << response.body();
  EXPECT_EQ(json_of(response)["display_name"], "ines2");
}

TEST_F(UsersApi, DuplicateUsernamesAre409) {
  const auto users = count("users");
  EXPECT_TRUE(
      is_error(create({{"username", "trainee"}, {"password", "kestrel-0942"}, {"role", "admin"}}),
               http::status::conflict, "username 'trainee' is already taken"));
  EXPECT_EQ(count("users"), users);
}

TEST_F(UsersApi, InvalidUsersAre422) {
  const auto users = count("users");
  const std::string name_rule = "username must be 3-32 characters of a-z, 0-9, '.', '_' or '-'";
  for (const std::string& name : std::vector<std::string>{
           "ab", std::string(33, 'a'), "Upper", "with space", "\u00fcmlaut", "semi;colon", ""}) {
    EXPECT_TRUE(
        is_error(create({{"username", name}, {"password", "kestrel-0942"}, {"role", "trainee"}}),
                 http::status::unprocessable_entity, name_rule))
        << name;
  }
  EXPECT_TRUE(
      is_error(create({{"username", "abc"}, {"password", "012345678"}, {"role", "trainee"}}),
               http::status::unprocessable_entity, "password must have at least 10 characters"));
  EXPECT_TRUE(
      is_error(create({{"username", "abc"}, {"password", "kestrel-0942"}, {"role", "root"}}),
               http::status::unprocessable_entity,
               "role must be trainee, instructor or admin (got 'root')"));
  EXPECT_TRUE(is_error(create({{"username", "abc"}, {"password", "kestrel-0942"}}),
                       http::status::unprocessable_entity, "missing field 'role'"));
  EXPECT_TRUE(is_error(create({{"username", "abc"},
                               {"password", "kestrel-0942"},
                               {"role", "trainee"},
                               {"admin", true}}),
                       http::status::unprocessable_entity, "unknown field 'admin'"));
  EXPECT_TRUE(
      is_error(create({{"username", "abc"}, {"password", 123456789012}, {"role", "trainee"}}),
               http::status::unprocessable_entity, "field 'password' must be a string"));
  EXPECT_EQ(count("users"), users);
}

// Which instructors teach a trainee decides what each instructor sees (access_matrix.cpp); admins
// set it when they create the trainee and change it later, and every change is audited.
TEST_F(UsersApi, AdminsChooseWhichInstructorsTeachATrainee) {
  const auto ines = user_id("instructor");
  const auto second = json_of(
      create({{"username", "ines2"}, {"password", "kestrel-0942"}, {"role", "instructor"}}))["id"];
  const auto created = create({{"username", "tess"},
                               {"password", "kestrel-0942"},
                               {"role", "trainee"},
                               {"instructor_ids", {ines}}});
  ASSERT_EQ(created.result(), http::status::created) << created.body();
  const auto tess = json_of(created)["id"].get<std::int64_t>();
  EXPECT_EQ(json_of(created)["instructor_ids"], nlohmann::json::array({ines}));
  EXPECT_TRUE(db::UsersRepo(db()).teaches(ines, tess));

  const auto path = "/api/users/" + std::to_string(tess) + "/instructors";
  const auto audits = count("audit_log WHERE action = 'user.instructors'");
  const auto changed = put(path, {{"instructor_ids", {second}}}, admin_);
  ASSERT_EQ(changed.result(), http::status::ok) << changed.body();
  EXPECT_EQ(json_of(changed)["instructor_ids"], nlohmann::json::array({second}));
  EXPECT_FALSE(db::UsersRepo(db()).teaches(ines, tess));
  EXPECT_EQ(count("audit_log WHERE action = 'user.instructors'"), audits + 1);

  // Bad requests change nothing.
  const auto trainee = user_id("trainee");
  EXPECT_TRUE(is_error(
      put(path, {{"instructor_ids", {trainee}}}, admin_), http::status::unprocessable_entity,
      "instructor_ids must name instructors; user " + std::to_string(trainee) + " is not one"));
  EXPECT_TRUE(is_error(put(path, {{"instructor_ids", {second, second}}}, admin_),
                       http::status::unprocessable_entity));
  EXPECT_TRUE(is_error(put(path, {{"instructor_ids", "ines"}}, admin_),
                       http::status::unprocessable_entity));
  EXPECT_TRUE(
      is_error(put(path, nlohmann::json::object(), admin_), http::status::unprocessable_entity));
  EXPECT_TRUE(is_error(put("/api/users/" + std::to_string(ines) + "/instructors",
                           {{"instructor_ids", {second}}}, admin_),
                       http::status::unprocessable_entity,
                       "instructor is not a trainee; only trainees have instructors"));
  EXPECT_TRUE(is_error(put("/api/users/999999/instructors", {{"instructor_ids", {}}}, admin_),
                       http::status::not_found));
  EXPECT_TRUE(is_error(create({{"username", "ines3"},
                               {"password", "kestrel-0942"},
                               {"role", "instructor"},
                               {"instructor_ids", {ines}}}),
                       http::status::unprocessable_entity, "only trainees have instructor_ids"));
  EXPECT_EQ(db::UsersRepo(db()).instructors_of(tess), std::vector<std::int64_t>{second});
}

// Names people read must read as they are stored: no control characters, no direction overrides;
// and a password must not be weak (db/password.h, docs/security.md).
TEST_F(UsersApi, NamesArePlainTextAndPasswordsNotWeak) {
  const auto users = count("users");
  const std::string override_name = "Eve \xE2\x80\xAEnimda";  // shows as "Eve admine"
  EXPECT_TRUE(is_error(create({{"username", "eve1"},
                               {"display_name", override_name},
                               {"password", "kestrel-0942"},
                               {"role", "trainee"}}),
                       http::status::unprocessable_entity,
                       "field 'display_name' must not contain control characters or text-direction "
                       "overrides"));
  EXPECT_TRUE(is_error(create({{"username", "eve1"},
                               {"display_name", std::string("Eve\0", 4)},
                               {"password", "kestrel-0942"},
                               {"role", "trainee"}}),
                       http::status::unprocessable_entity));
  for (const auto& [password, why] : std::vector<std::pair<std::string, std::string>>{
           {"aaaaaaaaaa", "password must not be one character repeated"},
           {"password12", "password is one of the most common passwords; choose another"},
           {"eve1eve1eve1", ""},
           {"\xF0\x9F\x98\x80\xF0\x9F\x98\x80\xF0\x9F\x98\x80\xF0\x9F\x98\x80",
            "password must have at least 10 characters"}}) {
    const auto response =
        create({{"username", "eve1"}, {"password", password}, {"role", "trainee"}});
    if (why.empty()) continue;  // checked below: it is acceptable
    EXPECT_TRUE(is_error(response, http::status::unprocessable_entity, why)) << password;
  }
  EXPECT_EQ(count("users"), users + 1);  // only "eve1eve1eve1" was acceptable
  EXPECT_TRUE(is_error(
      create({{"username", "frank.long"}, {"password", "Frank.Long"}, {"role", "trainee"}}),
      http::status::unprocessable_entity, "password must not be the username"));
}

}  // namespace
}  // namespace incise::server::test
