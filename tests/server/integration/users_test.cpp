// User administration on the real server.
#include <gtest/gtest.h>

#include <string>

#include "server_fixture.h"

namespace incise::server::test {
namespace {

using Users = ServerTest;

TEST_F(Users, AdminCreatesAUserWhoCanLogIn) {
  auto& admin = as(kAdmin);
  const auto created = admin.post("/api/users", {{"username", "new-instructor"},
                                                 {"password", "a long password"},
                                                 {"role", "instructor"},
                                                 {"display_name", "New Instructor"}});
  ASSERT_EQ(created.status, 201) << created.error();
  EXPECT_EQ(created.json()["username"], "new-instructor");
  EXPECT_EQ(created.json()["role"], "instructor");
  EXPECT_EQ(created.json()["display_name"], "New Instructor");

  const auto before = snapshot();
  EXPECT_TRUE(is_error(admin.post("/api/users", {{"username", "new-instructor"},
                                                 {"password", "another password"},
                                                 {"role", "trainee"}}),
                       409, "username 'new-instructor' is already taken"));
  EXPECT_TRUE(is_error(
      admin.post("/api/users",
                 {{"username", "x"}, {"password", "another password"}, {"role", "trainee"}}),
      422, "username must be 3-32 characters of a-z, 0-9, '.', '_' or '-'"));
  EXPECT_TRUE(
      is_error(admin.post("/api/users",
                          {{"username", "shorty"}, {"password", "short"}, {"role", "trainee"}}),
               422, "password must have at least 10 characters"));
  EXPECT_EQ(snapshot(), before);

  auto client = new_client();
  const auto login = client->login("new-instructor", "a long password");
  ASSERT_EQ(login.status, 200) << login.error();
  EXPECT_EQ(client->get("/api/me").json()["display_name"], "New Instructor");
  EXPECT_EQ(client->get("/api/bookings").status, 200);
  EXPECT_TRUE(is_error(client->get("/api/users"), 403));

  const auto users = admin.get("/api/users").json();
  EXPECT_EQ(users.size(), 5u) << users;  // the four demo logins and the new instructor
}

}  // namespace
}  // namespace incise::server::test
