#pragma once
// The events the simulation saw during a session (session_events, migration 009): a surgical
// scene's grasps, releases, cuts, collisions and never events, for the review's markers.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "db/database.h"

namespace incise::db {

struct SessionEvent {
  double t_s = 0;     // [s] of simulated time from the session's start, >= 0
  std::string kind;   // "grasp", "release", "cut", "collision" or "never_event"
  int hand = -1;      // 0 right, 1 left, -1 none
  std::string label;  // one line for the dashboard
  bool operator==(const SessionEvent&) const = default;
};

class SessionEventsRepo {
 public:
  explicit SessionEventsRepo(Database& db) : db_(db) {}

  // Stores (replacing any earlier) the session's events in ONE transaction: all or none. Throws
  // NotFound for an unknown session, std::invalid_argument for a negative or non-finite time,
  // ConstraintError for an unknown kind or a hand outside [-1, 1].
  void set(std::int64_t session_id, std::span<const SessionEvent> events);
  // In the order they were stored.
  std::vector<SessionEvent> list(std::int64_t session_id);

 private:
  Database& db_;
};

}  // namespace incise::db
