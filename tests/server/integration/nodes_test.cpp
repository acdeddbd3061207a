// Several server nodes on one database (the real incise-server twice, on an SQLite file or, in
// the pg/ run, on PostgreSQL): a node's start-up ends only the sessions it left running, and when
// a node dies (kill -9), the other ends its sessions once its heartbeats stop, closing their
// recordings at the last stored chunk.
#include <signal.h>

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "db/database.h"
#include "db/recordings_repo.h"
#include "db/training_repo.h"
#include "db/users_repo.h"
#include "server_fixture.h"

namespace incise::server::test {
namespace {

using namespace std::chrono_literals;

std::int64_t unix_now() {
  return std::chrono::duration_cast<std::chrono::seconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// A running session of `node`, as that node would have written it, with an open recording that
// holds one chunk. Returns {session, recording}.
std::pair<std::int64_t, std::int64_t> running_session(db::Database& db, const std::string& node) {
  db::TrainingRepo training(db);
  const auto trainee = db::UsersRepo(db).find_by_username("trainee")->id;
  const auto session =
      training.create_session(trainee, std::nullopt, "palpation", unix_now(), std::nullopt, node);
  training.set_session_state(session, "running", unix_now());
  db::RecordingsRepo recordings(db);
  const auto recording =
      recordings.create(session, "scenes/palpation.json", "1:test", 1, 500.0, unix_now());
  const std::vector<std::uint8_t> chunk = {1, 2, 3, 4};
  recordings.append_chunk(recording, 0, 0, chunk, 0.5);
  return {session, recording};
}

std::string state_of(db::Database& db, std::int64_t session) {
  return db::TrainingRepo(db).find_session(session)->state;
}

TEST(Nodes, AStartEndsOnlyItsOwnSessionsAndTheOthersEndADeadNodes) {
  signal(SIGPIPE, SIG_IGN);
  ServerProcess a({"--node-id", "node-a", "--node-timeout", "3"});
  db::Database db(a.database());
  const auto [left_by_b, left_by_b_recording] = running_session(db, "node-b");
  const auto [of_a, of_a_recording] = running_session(db, "node-a");

  // Node b starts: the session it left running ends, node a's runs on.
  ServerProcess b({"--node-id", "node-b", "--node-timeout", "3"}, &a);
  EXPECT_EQ(state_of(db, left_by_b), "aborted");
  EXPECT_EQ(db::RecordingsRepo(db).find(left_by_b_recording)->state, "complete");
  EXPECT_EQ(state_of(db, of_a), "running") << "another node's session was ended";

  // Node b dies with a session running: node a ends it after b's heartbeats stop (3 s), and its
  // recording keeps the chunk it stored.
  const auto [of_b, of_b_recording] = running_session(db, "node-b");
  b.process().send_signal(SIGKILL);
  const auto killed = std::chrono::steady_clock::now();
  while (state_of(db, of_b) == "running" && std::chrono::steady_clock::now() - killed < 15s)
    std::this_thread::sleep_for(100ms);
  EXPECT_EQ(state_of(db, of_b), "aborted") << a.process().stderr_text();
  const auto recording = db::RecordingsRepo(db).find(of_b_recording);
  EXPECT_EQ(recording->state, "complete");
  EXPECT_EQ(db::RecordingsRepo(db).chunks(of_b_recording).size(), 1u);
  EXPECT_NE(a.process().stderr_text().find("node node-b missed its heartbeats"), std::string::npos)
      << a.process().stderr_text();
  EXPECT_EQ(state_of(db, of_a), "running") << "the live node's own session";
  EXPECT_EQ(db::RecordingsRepo(db).find(of_a_recording)->state, "recording");
}

}  // namespace
}  // namespace incise::server::test
