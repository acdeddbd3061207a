// An admin disables and re-enables users and resets their passwords; a user whose password was
// reset must choose a new one before anything else (server/api/users_api.cpp, auth_api.cpp).
// Through the router on a real SQLite file, logging in as a person would.
#include <gtest/gtest.h>

#include <string>

#include "api_test_app.h"
#include "db/audit_repo.h"
#include "db/users_repo.h"

namespace incise::server::test {
namespace {

constexpr const char* kTraineePassword = "incise-trainee-demo";

class UserAdminApi : public ApiTest {
 protected:
  void SetUp() override {
    ApiTest::SetUp();
    admin_ = session_of(Who::admin);
    trainee_ = user_id("trainee");
  }
  Response login(const std::string& username, const std::string& password) {
    return call({http::verb::post, "/api/login",
                 nlohmann::json{{"username", username}, {"password", password}}.dump()});
  }
  // The session cookie's value from a login response.
  static std::string token_of(const Response& response) {
    const std::string cookie(response[http::field::set_cookie]);
    const auto start = cookie.find('=') + 1;
    return cookie.substr(start, cookie.find(';') - start);
  }
  Response patch_user(std::int64_t id, const nlohmann::json& body, const std::string& token) {
    return call({http::verb::patch, "/api/users/" + std::to_string(id), body.dump(), token});
  }
  db::AuditEntry last_audit() { return db::AuditRepo(db()).list(1).front(); }

  std::string admin_;
  std::int64_t trainee_ = 0;
};

TEST_F(UserAdminApi, ADisabledUserCannotLogInAndTheirSessionsEnd) {
  const auto signed_in = session_of(Who::trainee);
  ASSERT_EQ(get("/api/bookings", signed_in).result(), http::status::ok);
  const auto audits = count("audit_log");

  const auto disabled = patch_user(trainee_, {{"disabled", true}}, admin_);
  ASSERT_EQ(disabled.result(), http::status::ok) << disabled.body();
  EXPECT_EQ(json_of(disabled)["disabled"], true);
  // Logged out at once, and the right password no longer lets them in.
  EXPECT_TRUE(is_error(get("/api/bookings", signed_in), http::status::unauthorized));
  EXPECT_TRUE(is_error(login("trainee", kTraineePassword), http::status::forbidden,
                       "this account is disabled; ask an admin"));
  // A wrong password says no more than it always does.
  EXPECT_TRUE(is_error(login("trainee", "not the password"), http::status::unauthorized,
                       "wrong username or password"));
  EXPECT_EQ(count("audit_log"), audits + 1);
  auto entry = last_audit();
  EXPECT_EQ(entry.action, "user.disable");
  EXPECT_EQ(entry.detail, "trainee");
  EXPECT_EQ(nlohmann::json::parse(entry.before_json), (nlohmann::json{{"disabled", false}}));
  EXPECT_EQ(nlohmann::json::parse(entry.after_json), (nlohmann::json{{"disabled", true}}));

  // Disabling twice changes nothing and records nothing.
  ASSERT_EQ(patch_user(trainee_, {{"disabled", true}}, admin_).result(), http::status::ok);
  EXPECT_EQ(count("audit_log"), audits + 1);

  const auto enabled = patch_user(trainee_, {{"disabled", false}}, admin_);
  ASSERT_EQ(enabled.result(), http::status::ok) << enabled.body();
  EXPECT_EQ(json_of(enabled)["disabled"], false);
  EXPECT_EQ(last_audit().action, "user.enable");
  EXPECT_EQ(login("trainee", kTraineePassword).result(), http::status::ok);
}

TEST_F(UserAdminApi, DisablingIsAnAdminsAndNeverOfThemself) {
  const auto users = json_of(get("/api/users", admin_)).dump();
  EXPECT_TRUE(is_error(patch_user(trainee_, {{"disabled", true}}, session_of(Who::instructor)),
                       http::status::forbidden));
  EXPECT_TRUE(is_error(patch_user(user_id("admin"), {{"disabled", true}}, admin_),
                       http::status::conflict, "you cannot disable your own account"));
  EXPECT_TRUE(is_error(patch_user(9999, {{"disabled", true}}, admin_), http::status::not_found,
                       "user 9999 does not exist"));
  EXPECT_TRUE(is_error(patch_user(trainee_, {{"disabled", "yes"}}, admin_),
                       http::status::unprocessable_entity));
  EXPECT_TRUE(is_error(patch_user(trainee_, {{"role", "admin"}}, admin_),
                       http::status::unprocessable_entity));
  EXPECT_EQ(json_of(get("/api/users", admin_)).dump(), users);
}

TEST_F(UserAdminApi, AResetPasswordMustBeReplacedBeforeAnythingElse) {
  const auto before = session_of(Who::trainee);
  const std::string reset_path = "/api/users/" + std::to_string(trainee_) + "/password";
  EXPECT_TRUE(is_error(post(reset_path, {{"password", "short"}}, admin_),
                       http::status::unprocessable_entity,
                       "password must have at least 10 characters"));
  EXPECT_TRUE(
      is_error(post(reset_path, {{"password", "temporary-123"}}, session_of(Who::instructor)),
               http::status::forbidden));
  const auto reset = post(reset_path, {{"password", "temporary-123"}}, admin_);
  ASSERT_EQ(reset.result(), http::status::ok) << reset.body();
  EXPECT_EQ(json_of(reset)["must_change_password"], true);
  const auto entry = last_audit();
  EXPECT_EQ(entry.action, "user.password_reset");
  EXPECT_EQ(entry.before_json + entry.after_json + entry.detail,
            R"({"must_change_password":false}{"must_change_password":true}trainee)");
  // The old session ended; the old password no longer works; the temporary one does.
  EXPECT_TRUE(is_error(get("/api/me", before), http::status::unauthorized));
  EXPECT_TRUE(is_error(login("trainee", kTraineePassword), http::status::unauthorized));
  const auto logged_in = login("trainee", "temporary-123");
  ASSERT_EQ(logged_in.result(), http::status::ok) << logged_in.body();
  EXPECT_EQ(json_of(logged_in)["user"]["must_change_password"], true);
  const auto token = token_of(logged_in);

  // Until they choose a new one, only who they are and the change itself answer.
  EXPECT_EQ(json_of(get("/api/me", token))["must_change_password"], true);
  EXPECT_TRUE(
      is_error(get("/api/bookings", token), http::status::forbidden,
               "choose a new password first: an admin reset yours (POST /api/me/password)"));
  EXPECT_TRUE(is_error(
      post("/api/me/password",
           {{"current_password", "wrong-one-123"}, {"new_password", "mine-now-123"}}, token),
      http::status::unprocessable_entity, "current_password is wrong"));
  EXPECT_TRUE(is_error(
      post("/api/me/password",
           {{"current_password", "temporary-123"}, {"new_password", "temporary-123"}}, token),
      http::status::unprocessable_entity, "new_password must differ from the current one"));
  const auto changed =
      post("/api/me/password",
           {{"current_password", "temporary-123"}, {"new_password", "mine-now-123"}}, token);
  ASSERT_EQ(changed.result(), http::status::ok) << changed.body();
  EXPECT_EQ(json_of(changed)["must_change_password"], false);
  EXPECT_EQ(get("/api/bookings", token).result(), http::status::ok);
  EXPECT_EQ(last_audit().action, "user.password_change");
  EXPECT_EQ(login("trainee", "mine-now-123").result(), http::status::ok);
  // No password ever reaches the audit log.
  for (const auto& e : db::AuditRepo(db()).list()) {
    const auto text = e.detail + e.before_json + e.after_json;
    EXPECT_EQ(text.find("temporary-123"), std::string::npos) << e.action;
    EXPECT_EQ(text.find("mine-now-123"), std::string::npos) << e.action;
  }
}

TEST_F(UserAdminApi, ChangingOnesPasswordEndsOtherLoginsAndGuessingIsLimited) {
  const auto here = token_of(login("trainee", kTraineePassword));
  const auto elsewhere = session_of(Who::trainee);  // say, a cookie someone else holds
  // Guesses at the current password count like failed logins: after a few, 429 with the wait.
  int guesses = 0;
  for (; guesses < 20; ++guesses) {
    const auto r = post("/api/me/password",
                        {{"current_password", "guess-" + std::to_string(guesses) + "-xyz"},
                         {"new_password", "mine-now-123"}},
                        here);
    if (r.result() == http::status::too_many_requests) break;
    ASSERT_TRUE(is_error(r, http::status::unprocessable_entity, "current_password is wrong"));
  }
  EXPECT_LT(guesses, 20);
  EXPECT_TRUE(is_error(
      post("/api/me/password",
           {{"current_password", kTraineePassword}, {"new_password", "mine-now-123"}}, here),
      http::status::too_many_requests));
  set_now(now() + 3600);  // the wait is over
  const auto changed =
      post("/api/me/password",
           {{"current_password", kTraineePassword}, {"new_password", "mine-now-123"}}, here);
  ASSERT_EQ(changed.result(), http::status::ok) << changed.body();
  EXPECT_EQ(get("/api/me", here).result(), http::status::ok);                    // this login stays
  EXPECT_TRUE(is_error(get("/api/me", elsewhere), http::status::unauthorized));  // the other ends
}

TEST_F(UserAdminApi, AnAdminResetsOnlyOthersPasswords) {
  EXPECT_TRUE(is_error(post("/api/users/" + std::to_string(user_id("admin")) + "/password",
                            {{"password", "temporary-123"}}, admin_),
                       http::status::conflict));
  EXPECT_FALSE(db::UsersRepo(db()).find(user_id("admin"))->must_change_password);
}

}  // namespace
}  // namespace incise::server::test
