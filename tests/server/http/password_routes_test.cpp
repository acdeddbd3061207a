// Which requests check or hash a password, and so run on the password workers rather than an I/O
// thread (server/http/http_session.h: checks_password), which are long reads (is_long_read); and
// ApiContext::hash_password.
#include <gtest/gtest.h>

#include <string>

#include "db/password.h"
#include "server/api/api_context.h"
#include "server/http/http_session.h"
#include "tests/server/api/api_test_app.h"

namespace incise::server::test {
namespace {

Request request(http::verb method, const std::string& target) {
  Request r{method, target, 11};
  r.set(http::field::host, "localhost");
  return r;
}

TEST(PasswordRoutes, EveryRequestThatHashesOrChecksAPasswordRunsOnTheWorkers) {
  for (const char* target :
       {"/api/login", "/api/me/password", "/api/users", "/api/users/7/password",
        "/api/users/12/password?x=1", "/api/login?next=/"}) {
    EXPECT_TRUE(checks_password(request(http::verb::post, target))) << target;
    EXPECT_FALSE(checks_password(request(http::verb::get, target))) << target;
  }
  for (const char* target :
       {"/api/users/7", "/api/users//password", "/api/users/7/8/password", "/api/me",
        "/api/users/password", "/api/usersx", "/api/login/x", "/api/users/7/passwordx"}) {
    EXPECT_FALSE(checks_password(request(http::verb::post, target))) << target;
  }
}

// The long reads (is_long_read) run on their own workers, for the same reason.
TEST(LongReadRoutes, TheReviewAndTheExportRunOnTheLongReadWorkers) {
  for (const char* target :
       {"/api/sessions/7/review", "/api/sessions/7/review?x=1", "/api/exports/scores.csv",
        "/api/exports/scores.csv?from=2026-01-01"}) {
    EXPECT_TRUE(is_long_read(request(http::verb::get, target))) << target;
    EXPECT_FALSE(is_long_read(request(http::verb::post, target))) << target;
  }
  for (const char* target :
       {"/api/sessions//review", "/api/sessions/7/8/review", "/api/sessions/7", "/api/sessions",
        "/api/sessions/7/reviewx", "/api/exports/scores.csvx", "/api/recordings/3/replay"}) {
    EXPECT_FALSE(is_long_read(request(http::verb::get, target))) << target;
  }
  // A calibration's upload: its JSON and CSV parsed and stored off the I/O threads.
  EXPECT_TRUE(is_long_read(request(http::verb::post, "/api/calibration/jobs")));
  EXPECT_FALSE(is_long_read(request(http::verb::get, "/api/calibration/jobs")));
  EXPECT_FALSE(is_long_read(request(http::verb::post, "/api/calibration/jobs/3/cancel")));
}

// Only the upload may carry a body larger than the API's 64 KiB.
TEST(BodyLimits, OnlyTheCalibrationUploadTakesEightMebibytes) {
  ServerConfig config;
  EXPECT_EQ(body_limit_for(http::verb::post, "/api/calibration/jobs", config), kUploadBodyLimit);
  EXPECT_EQ(body_limit_for(http::verb::put, "/api/calibration/jobs", config),
            config.api_body_limit);
  EXPECT_EQ(body_limit_for(http::verb::post, "/api/calibration/jobs?x=1", config),
            kUploadBodyLimit);
  EXPECT_EQ(body_limit_for(http::verb::post, "/api/calibration/jobs/1", config),
            config.api_body_limit);
  EXPECT_EQ(body_limit_for(http::verb::post, "/api/users", config), config.api_body_limit);
}

class HashPassword : public ApiTest {};

TEST_F(HashPassword, GivesAHashThatVerifies) {
  const Request r = request(http::verb::post, "/api/users");
  ApiContext ctx(r, app(), Caller{"127.0.0.1", false});
  const db::PasswordHash hash = ctx.hash_password("correct horse battery");
  EXPECT_TRUE(db::verify_password("correct horse battery", hash.value));
  EXPECT_FALSE(db::verify_password("correct horse battery!", hash.value));
}

}  // namespace
}  // namespace incise::server::test
