// Stopping the real server with SIGTERM.
#include <signal.h>

#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "db/database.h"
#include "db/statement.h"
#include "server_fixture.h"
#include "tests/support/ws_client.h"

namespace incise::server::test {
namespace {

using namespace std::chrono_literals;

using Shutdown = ServerTest;

TEST_F(Shutdown, SigtermStopsCleanlyAndLeavesASoundDatabase) {
  // Some state to persist, an idle keep-alive connection and a connected agent.
  auto& trainee = as(kTrainee);
  const auto start = quarter_hour_in_days(1);
  const auto booked = trainee.post(
      "/api/bookings",
      {{"station_id", 1}, {"starts_at", utc_text(start)}, {"ends_at", utc_text(start + 900)}});
  ASSERT_EQ(booked.status, 201) << booked.error();
  WsClient agent("127.0.0.1", server().port());
  agent.send_text(nlohmann::json{{"type", "hello"},
                                 {"protocol", 1},
                                 {"station_token", kStationToken},
                                 {"agent", "server_integration_tests"}}
                      .dump());
  ASSERT_FALSE(agent.read().closed);

  const auto t0 = std::chrono::steady_clock::now();
  server().process().send_signal(SIGTERM);
  const auto goodbye = agent.read();
  EXPECT_EQ(goodbye.close_code, 1001) << goodbye.error;
  EXPECT_EQ(goodbye.close_reason, "server shutting down");
  EXPECT_EQ(server().process().wait_for_exit(3s), 0) << server().process().stderr_text();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 3s);
  EXPECT_NE(server().process().stderr_text().find("incise-server: stopped"), std::string::npos);

  db::Database db(server().database());
  if (db.dialect() == db::Dialect::sqlite) {
    auto check = db.prepare("PRAGMA integrity_check");
    ASSERT_TRUE(check.step());
    EXPECT_EQ(check.text(0), "ok");
  }
  auto count = db.prepare("SELECT COUNT(*) FROM bookings WHERE status = 'active'");
  ASSERT_TRUE(count.step());
  EXPECT_EQ(count.int64(0), 1);
}

}  // namespace
}  // namespace incise::server::test
