#include "server/node_heartbeat.h"

#include <chrono>
#include <iostream>

#include "db/nodes_repo.h"
#include "server/wire_text.h"

namespace incise::server {

NodeHeartbeat::NodeHeartbeat(db::ConnectionPool& pool, std::string node_id, std::string address,
                             int timeout_s, std::function<std::int64_t()> clock,
                             std::function<void(db::Database&)> after_beat)
    : pool_(pool),
      node_id_(std::move(node_id)),
      address_(std::move(address)),
      timeout_s_(timeout_s),
      clock_(std::move(clock)),
      after_beat_(std::move(after_beat)) {
  // Six beats per timeout: a node is taken for dead only after missing several in a row.
  const auto period = std::chrono::milliseconds(1000 * timeout_s_ / 6);
  thread_ = std::thread([this, period] {
    std::unique_lock lock(mutex_);
    while (!stopping_) {
      lock.unlock();
      beat();
      lock.lock();
      wake_.wait_for(lock, period, [this] { return stopping_; });
    }
  });
}

NodeHeartbeat::~NodeHeartbeat() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

bool NodeHeartbeat::beat() {
  try {
    auto db = pool_.acquire();
    db::NodesRepo nodes(*db);
    const auto now = clock_();
    nodes.heartbeat(node_id_, address_, now);
    db::EndedSessions ended;
    for (const auto& node : nodes.sweep(node_id_, now, timeout_s_, ended)) {
      std::cerr << "incise-server: node " << node << " missed its heartbeats for " << timeout_s_
                << " s; its sessions are aborted\n";
    }
    for (const auto id : ended.sessions)
      std::cerr << "incise-server: session " << id << " of a dead node marked aborted\n";
    for (const auto id : ended.recordings)
      std::cerr << "incise-server: recording " << id << " of a dead node closed as it was\n";
    if (after_beat_) after_beat_(*db);
    return true;
  } catch (const std::exception& e) {
    std::cerr << "incise-server: heartbeat of node " << node_id_
              << " failed (tried again shortly): " << valid_utf8(e.what()) << "\n";
    return false;
  }
}

}  // namespace incise::server
