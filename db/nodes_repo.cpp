#include "db/nodes_repo.h"

#include <algorithm>

#include "db/statement.h"
#include "db/transaction.h"

namespace incise::db {

void NodesRepo::start(const std::string& id, const std::string& address, std::int64_t now) {
  db_.prepare(
         "INSERT INTO nodes (id, address, started_at, heartbeat_at) VALUES (?1, ?2, ?3, ?3) ON "
         "CONFLICT (id) DO UPDATE SET address = excluded.address, started_at = "
         "excluded.started_at, heartbeat_at = excluded.heartbeat_at")
      .bind(1, id)
      .bind(2, address)
      .bind(3, now)
      .run();
}

void NodesRepo::heartbeat(const std::string& id, const std::string& address, std::int64_t now) {
  // A node swept by the others while it was cut off comes back: registered again.
  db_.prepare(
         "INSERT INTO nodes (id, address, started_at, heartbeat_at) VALUES (?1, ?2, ?3, ?3) ON "
         "CONFLICT (id) DO UPDATE SET address = excluded.address, heartbeat_at = "
         "excluded.heartbeat_at")
      .bind(1, id)
      .bind(2, address)
      .bind(3, now)
      .run();
}

std::vector<NodeRecord> NodesRepo::list() {
  auto q = db_.prepare("SELECT id, address, started_at, heartbeat_at FROM nodes ORDER BY id");
  std::vector<NodeRecord> out;
  while (q.step())
    out.push_back({q.text(0), q.text(1), q.int64(2), q.int64(3)});
  return out;
}

EndedSessions NodesRepo::end_sessions_of(const std::string& node, std::int64_t now,
                                         bool and_unowned) {
  constexpr const char* kOwned = "(node_id = ?1 OR (?2 = 1 AND node_id IS NULL))";
  EndedSessions ended;
  Transaction tx(db_);
  {
    // The recordings first, while their sessions still say whose they are. Closed as they are:
    // every committed chunk stays, replayable up to the last one.
    auto q = db_.prepare(std::string("UPDATE recordings SET state = 'complete' WHERE state = "
                                     "'recording' AND session_id IN (SELECT id FROM sessions "
                                     "WHERE ") +
                         kOwned + ") RETURNING id");
    q.bind(1, node).bind(2, and_unowned ? 1 : 0);
    while (q.step())
      ended.recordings.push_back(q.int64(0));
  }
  {
    auto q = db_.prepare(
        std::string("UPDATE sessions SET state = 'aborted', ended_at = ?3 WHERE state IN "
                    "('running', 'paused') AND ") +
        kOwned + " RETURNING id");
    q.bind(1, node).bind(2, and_unowned ? 1 : 0).bind(3, now);
    while (q.step())
      ended.sessions.push_back(q.int64(0));
  }
  db_.prepare("DELETE FROM station_links WHERE node_id = ?").bind(1, node).run();
  tx.commit();
  return ended;
}

std::vector<std::string> NodesRepo::sweep(const std::string& self, std::int64_t now,
                                          std::int64_t timeout_s, EndedSessions& ended) {
  std::vector<std::string> swept;
  Transaction tx(db_);  // one sweeper at a time; the others then find nothing left to do
  {
    auto q = db_.prepare("SELECT id FROM nodes WHERE id != ? AND heartbeat_at < ? ORDER BY id");
    q.bind(1, self).bind(2, now - timeout_s);
    while (q.step())
      swept.push_back(q.text(0));
  }
  for (const auto& node : swept) {
    auto of_node = end_sessions_of(node, now, false);  // a savepoint of this transaction
    ended.sessions.insert(ended.sessions.end(), of_node.sessions.begin(), of_node.sessions.end());
    ended.recordings.insert(ended.recordings.end(), of_node.recordings.begin(),
                            of_node.recordings.end());
    // Its calibration jobs end too: nobody else runs them, and a cancel would wait forever.
    db_.prepare(
           "UPDATE calibration_jobs SET status = 'failed', error = 'its server node stopped', "
           "finished_at = ? WHERE node_id = ? AND status IN ('queued', 'running')")
        .bind(1, now)
        .bind(2, node)
        .run();
    db_.prepare("DELETE FROM nodes WHERE id = ?").bind(1, node).run();
  }
  tx.commit();
  return swept;
}

namespace {
constexpr const char* kNodeColumns = "n.id, n.address, n.started_at, n.heartbeat_at";

std::optional<NodeRecord> one_node(Statement& q) {
  if (!q.step()) return std::nullopt;
  return NodeRecord{q.text(0), q.text(1), q.int64(2), q.int64(3)};
}
}  // namespace

std::optional<NodeRecord> NodesRepo::node_of_live_session(std::int64_t session_id) {
  auto q = db_.prepare(std::string("SELECT ") + kNodeColumns +
                       " FROM sessions s JOIN nodes n ON n.id = s.node_id WHERE s.id = ? AND "
                       "s.state IN ('running', 'paused')");
  q.bind(1, session_id);
  return one_node(q);
}

std::optional<NodeRecord> NodesRepo::node_of_station(std::int64_t station_id) {
  auto q = db_.prepare(std::string("SELECT ") + kNodeColumns +
                       " FROM station_links l JOIN nodes n ON n.id = l.node_id WHERE "
                       "l.station_id = ?");
  q.bind(1, station_id);
  return one_node(q);
}

std::string NodesRepo::link_station(std::int64_t station_id, const std::string& node,
                                    std::int64_t now, std::int64_t timeout_s) {
  Transaction tx(db_);  // the check and the claim together: two nodes cannot both link
  if (const auto holder = node_of_station(station_id);
      holder && holder->id != node && holder->heartbeat_at >= now - timeout_s) {
    return holder->id;
  }
  db_.prepare(
         "INSERT INTO station_links (station_id, node_id, linked_at) VALUES (?1, ?2, ?3) ON "
         "CONFLICT (station_id) DO UPDATE SET node_id = excluded.node_id, linked_at = "
         "excluded.linked_at")
      .bind(1, station_id)
      .bind(2, node)
      .bind(3, now)
      .run();
  tx.commit();
  return {};
}

void NodesRepo::unlink_station(std::int64_t station_id, const std::string& node) {
  db_.prepare("DELETE FROM station_links WHERE station_id = ? AND node_id = ?")
      .bind(1, station_id)
      .bind(2, node)
      .run();
}

std::vector<std::int64_t> NodesRepo::reconcile_links(const std::string& node,
                                                     const std::vector<std::int64_t>& stations,
                                                     std::int64_t now, std::int64_t timeout_s) {
  const auto recorded = [&] {
    auto q = db_.prepare(
        "SELECT station_id FROM station_links WHERE node_id = ? ORDER BY "
        "station_id");
    q.bind(1, node);
    std::vector<std::int64_t> out;
    while (q.step())
      out.push_back(q.int64(0));
    return out;
  };
  std::vector<std::int64_t> elsewhere;
  if (recorded() == stations) return elsewhere;  // the usual beat: nothing to write
  Transaction tx(db_);
  for (const auto station : recorded()) {
    if (!std::binary_search(stations.begin(), stations.end(), station)) {
      unlink_station(station, node);
    }
  }
  for (const auto station : stations) {
    if (const auto holder = link_station(station, node, now, timeout_s); !holder.empty()) {
      elsewhere.push_back(station);
    }
  }
  tx.commit();
  return elsewhere;
}

std::vector<std::int64_t> NodesRepo::linked_stations(std::int64_t now, std::int64_t timeout_s) {
  auto q = db_.prepare(
      "SELECT l.station_id FROM station_links l JOIN nodes n ON n.id = l.node_id WHERE "
      "n.heartbeat_at >= ? ORDER BY l.station_id");
  q.bind(1, now - timeout_s);
  std::vector<std::int64_t> out;
  while (q.step())
    out.push_back(q.int64(0));
  return out;
}

}  // namespace incise::db
