// Tests for db/nodes_repo.h on the suite's engine: heartbeats, a node ending only its own
// sessions, and the sweep of a node that stopped beating.
#include "db/nodes_repo.h"

#include <gtest/gtest.h>

#include "db/recordings_repo.h"
#include "db/statement.h"
#include "db/training_repo.h"
#include "temp_database.h"

namespace incise::db {
namespace {

class NodesRepoTest : public test::DbTest {
 protected:
  // A running session of `node` ("" for none) with an open recording and one stored chunk.
  std::pair<std::int64_t, std::int64_t> live_session(const std::string& node) {
    const auto session =
        training_.create_session(ann_, std::nullopt, "palpation", 10, std::nullopt, node);
    training_.set_session_state(session, "running", 11);
    const auto recording = recordings_.create(session, "palpation", "1:abc", 7, 500.0, 11);
    const std::vector<std::uint8_t> bytes = {1, 2, 3};
    recordings_.append_chunk(recording, 0, 0, bytes, 0.5);
    return {session, recording};
  }
  std::string state_of(std::int64_t session) { return training_.find_session(session)->state; }
  std::string recording_state(std::int64_t recording) { return recordings_.find(recording)->state; }

  std::int64_t ann_ = test::add_user(db(), "ann");
  TrainingRepo training_{db()};
  RecordingsRepo recordings_{db()};
  NodesRepo nodes_{db()};
};

TEST_F(NodesRepoTest, StartAndHeartbeatsKeepOneRowPerNode) {
  nodes_.start("a", "http://10.0.0.1:8080", 100);
  nodes_.heartbeat("a", "http://10.0.0.1:8080", 105);
  nodes_.start("b", "", 103);
  const auto all = nodes_.list();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].id, "a");
  EXPECT_EQ(all[0].started_at, 100);
  EXPECT_EQ(all[0].heartbeat_at, 105);
  EXPECT_EQ(all[1].id, "b");
  nodes_.start("a", "http://10.0.0.2:8080", 200);  // restarted elsewhere
  EXPECT_EQ(nodes_.list()[0].started_at, 200);
  EXPECT_EQ(nodes_.list()[0].address, "http://10.0.0.2:8080");
}

TEST_F(NodesRepoTest, ANodeEndsOnlyItsOwnSessionsAndKeepsTheirChunks) {
  const auto [mine, my_recording] = live_session("a");
  const auto [theirs, their_recording] = live_session("b");
  const auto [old, old_recording] = live_session("");
  const auto ended = nodes_.end_sessions_of("a", 50, false);
  EXPECT_EQ(ended.sessions, std::vector<std::int64_t>{mine});
  EXPECT_EQ(ended.recordings, std::vector<std::int64_t>{my_recording});
  EXPECT_EQ(state_of(mine), "aborted");
  EXPECT_EQ(training_.find_session(mine)->ended_at, 50);
  EXPECT_EQ(recording_state(my_recording), "complete");
  EXPECT_EQ(recordings_.chunks(my_recording).size(), 1u) << "the stored chunk stays";
  EXPECT_EQ(state_of(theirs), "running") << "another node's session";
  EXPECT_EQ(recording_state(their_recording), "recording");
  EXPECT_EQ(state_of(old), "running");

  // With and_unowned, sessions from before nodes end too; a finished session is never touched.
  training_.set_session_state(theirs, "finished", 60);
  const auto more = nodes_.end_sessions_of("a", 70, true);
  EXPECT_EQ(more.sessions, std::vector<std::int64_t>{old});
  EXPECT_EQ(state_of(theirs), "finished");
}

TEST_F(NodesRepoTest, TheSweepEndsTheSessionsOfNodesThatStoppedBeating) {
  nodes_.start("self", "", 0);
  nodes_.start("alive", "", 0);
  nodes_.start("dead", "", 0);
  const auto [alive_session, alive_recording] = live_session("alive");
  const auto [dead_session, dead_recording] = live_session("dead");
  nodes_.heartbeat("alive", "", 95);
  nodes_.heartbeat("dead", "", 60);
  EndedSessions ended;
  // At 100 with a 30 s timeout: "dead" beat last at 60, "alive" at 95; "self" never counts.
  EXPECT_EQ(nodes_.sweep("self", 100, 30, ended), std::vector<std::string>{"dead"});
  EXPECT_EQ(ended.sessions, std::vector<std::int64_t>{dead_session});
  EXPECT_EQ(ended.recordings, std::vector<std::int64_t>{dead_recording});
  EXPECT_EQ(state_of(dead_session), "aborted");
  EXPECT_EQ(state_of(alive_session), "running");
  EXPECT_EQ(nodes_.list().size(), 2u) << "the dead node is forgotten";
  EndedSessions again;
  nodes_.heartbeat("self", "", 100);
  EXPECT_TRUE(nodes_.sweep("alive", 100, 30, again).empty()) << "a second sweeper finds nothing";
  EXPECT_TRUE(again.sessions.empty());
}

TEST_F(NodesRepoTest, AStationLinksToOneLiveNodeAtATime) {
  const auto bench = test::add_station(db(), "Bench");
  nodes_.start("a", "10.0.0.1:8080", 100);
  nodes_.start("b", "10.0.0.2:8080", 100);
  EXPECT_FALSE(nodes_.node_of_station(bench));
  EXPECT_EQ(nodes_.link_station(bench, "a", 101, 30), "");
  ASSERT_TRUE(nodes_.node_of_station(bench));
  EXPECT_EQ(nodes_.node_of_station(bench)->address, "10.0.0.1:8080");
  // Node b is refused while a beats; a's own relink (a reconnect there) is not.
  EXPECT_EQ(nodes_.link_station(bench, "b", 110, 30), "a");
  EXPECT_EQ(nodes_.link_station(bench, "a", 111, 30), "");
  EXPECT_EQ(nodes_.linked_stations(111, 30), std::vector<std::int64_t>{bench});
  // Node a falls silent (last beat at 100): after the timeout the link is b's to take, and a
  // station linked to a silent node counts as offline.
  EXPECT_TRUE(nodes_.linked_stations(131, 30).empty());
  EXPECT_EQ(nodes_.link_station(bench, "b", 131, 30), "");
  EXPECT_EQ(nodes_.node_of_station(bench)->id, "b");
  // Only the holder drops it.
  nodes_.unlink_station(bench, "a");
  EXPECT_EQ(nodes_.node_of_station(bench)->id, "b");
  nodes_.unlink_station(bench, "b");
  EXPECT_FALSE(nodes_.node_of_station(bench));
}

TEST_F(NodesRepoTest, AHeartbeatMakesTheLinksMatchTheAgentsANodeHolds) {
  const auto bench = test::add_station(db(), "Bench");
  const auto surgical = test::add_station(db(), "Surgical");
  const auto knee = test::add_station(db(), "Knee");
  nodes_.start("a", "10.0.0.1:8080", 100);
  nodes_.start("b", "10.0.0.2:8080", 100);
  // Node a lost its rows in a sweep (cut off, yet alive) but kept its agents of bench and
  // surgical; it still has a row of knee whose unlink failed; node b holds nothing yet.
  nodes_.link_station(knee, "a", 100, 30);
  const std::vector<std::int64_t> held = {bench, surgical};
  EXPECT_TRUE(nodes_.reconcile_links("a", held, 101, 30).empty());
  EXPECT_EQ(nodes_.node_of_station(bench)->id, "a");
  EXPECT_EQ(nodes_.node_of_station(surgical)->id, "a");
  EXPECT_FALSE(nodes_.node_of_station(knee));
  // Nothing differs: the links stay as they are.
  EXPECT_TRUE(nodes_.reconcile_links("a", held, 150, 30).empty());
  EXPECT_EQ(nodes_.linked_stations(101, 30), held);
  // A station whose link a live node b holds stays b's, and is reported.
  nodes_.unlink_station(surgical, "a");
  nodes_.link_station(surgical, "b", 102, 30);
  EXPECT_EQ(nodes_.reconcile_links("a", held, 103, 30), std::vector<std::int64_t>{surgical});
  EXPECT_EQ(nodes_.node_of_station(surgical)->id, "b");
}

TEST_F(NodesRepoTest, AnEndedNodeLeavesNoLinksAndItsSessionsNoOwner) {
  const auto bench = test::add_station(db(), "Bench");
  nodes_.start("a", "10.0.0.1:8080", 100);
  const auto [session, recording] = live_session("a");
  ASSERT_TRUE(nodes_.node_of_live_session(session));
  EXPECT_EQ(nodes_.node_of_live_session(session)->address, "10.0.0.1:8080");
  training_.set_session_state(session, "paused", 12);
  EXPECT_TRUE(nodes_.node_of_live_session(session)) << "a paused session lives on its node";
  nodes_.link_station(bench, "a", 101, 30);
  nodes_.end_sessions_of("a", 120, false);
  EXPECT_FALSE(nodes_.node_of_station(bench));
  EXPECT_FALSE(nodes_.node_of_live_session(session)) << "an aborted session is nobody's";
  const auto [unowned, _] = live_session("");
  EXPECT_FALSE(nodes_.node_of_live_session(unowned));
}

}  // namespace
}  // namespace incise::db
