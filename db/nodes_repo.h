#pragma once
// The server nodes that share one database, each with a heartbeat, and what a node leaves behind
// when it stops: its live sessions are aborted and their open recordings closed at their last
// stored chunk. A node ends only its own sessions at start-up; another node's, only once that
// node has missed its heartbeats (docs/storage.md, "Nodes").
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/database.h"

namespace incise::db {

struct NodeRecord {
  std::string id;
  std::string address;  // how other nodes reach it ("" when unknown)
  std::int64_t started_at = 0;
  std::int64_t heartbeat_at = 0;
};

// What ending a node's sessions ended.
struct EndedSessions {
  std::vector<std::int64_t> sessions;    // marked aborted
  std::vector<std::int64_t> recordings;  // closed as they were
};

class NodesRepo {
 public:
  explicit NodesRepo(Database& db) : db_(db) {}

  // Registers the node (started now) or records its heartbeat.
  void start(const std::string& id, const std::string& address, std::int64_t now);
  void heartbeat(const std::string& id, const std::string& address, std::int64_t now);
  std::vector<NodeRecord> list();

  // The sessions `node` left running or paused are aborted (with `and_unowned`, also those no
  // node owns: from before nodes existed), their open recordings closed, its station links
  // dropped. One IMMEDIATE transaction.
  EndedSessions end_sessions_of(const std::string& node, std::int64_t now, bool and_unowned);
  // Every node but `self` whose last heartbeat is older than `timeout_s`: its sessions are ended as
  // above, its queued and running calibration jobs failed, and the node forgotten. Returns the
  // nodes swept; `ended` gains what was ended.
  std::vector<std::string> sweep(const std::string& self, std::int64_t now, std::int64_t timeout_s,
                                 EndedSessions& ended);

  // Where things run (docs/scale_out.md). The node running live session `session_id` (running or
  // paused), or nullopt: not live, or from before nodes.
  std::optional<NodeRecord> node_of_live_session(std::int64_t session_id);
  // The node holding `station_id`'s agent link, or nullopt.
  std::optional<NodeRecord> node_of_station(std::int64_t station_id);
  // Records that `node` holds the station's agent link, unless another node does whose heartbeat
  // is at most `timeout_s` old: then nothing changes and that node's id is returned ("" = linked).
  std::string link_station(std::int64_t station_id, const std::string& node, std::int64_t now,
                           std::int64_t timeout_s);
  // The link is gone, if `node` held it.
  void unlink_station(std::int64_t station_id, const std::string& node);
  // Makes the database say what this node knows: `node` holds exactly `stations` (ascending), its
  // agent links. Drops its rows of stations it has no link to (an unlink that failed), records the
  // missing ones (after a sweep of a node that was cut off but lived) unless another live node
  // holds them. Returns the stations it found held elsewhere. Writes only when something differs.
  std::vector<std::int64_t> reconcile_links(const std::string& node,
                                            const std::vector<std::int64_t>& stations,
                                            std::int64_t now, std::int64_t timeout_s);
  // The stations whose agent link a node holds that beat at most `timeout_s` ago, ascending.
  std::vector<std::int64_t> linked_stations(std::int64_t now, std::int64_t timeout_s);

 private:
  Database& db_;
};

}  // namespace incise::db
