#pragma once
// This node's heartbeat in the shared database, on a thread of its own: every timeout/6 seconds it
// records that the node is alive and sweeps the nodes that are not (db/nodes_repo.h), aborting
// the sessions they left running and closing their recordings at the last stored chunk. A failed
// beat (the database unreachable) is logged and tried again at the next one; it never stops the
// server.
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "db/connection_pool.h"

namespace incise::server {

class NodeHeartbeat {
 public:
  // `after_beat` runs after each successful beat on its connection (AppState's link check).
  NodeHeartbeat(db::ConnectionPool& pool, std::string node_id, std::string address, int timeout_s,
                std::function<std::int64_t()> clock,
                std::function<void(db::Database&)> after_beat = {});
  ~NodeHeartbeat();  // stops the thread
  NodeHeartbeat(const NodeHeartbeat&) = delete;
  NodeHeartbeat& operator=(const NodeHeartbeat&) = delete;

  // One beat and sweep, now (the thread calls it; tests may too). False when it failed.
  bool beat();

 private:
  db::ConnectionPool& pool_;
  const std::string node_id_;
  const std::string address_;
  const int timeout_s_;
  std::function<std::int64_t()> clock_;
  std::function<void(db::Database&)> after_beat_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace incise::server
