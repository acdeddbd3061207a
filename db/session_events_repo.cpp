#include "db/session_events_repo.h"

#include <cmath>
#include <stdexcept>

#include "db/db_error.h"
#include "db/statement.h"
#include "db/transaction.h"

namespace incise::db {

void SessionEventsRepo::set(std::int64_t session_id, std::span<const SessionEvent> events) {
  for (const SessionEvent& e : events) {
    if (!std::isfinite(e.t_s) || e.t_s < 0) {
      throw std::invalid_argument("session event \"" + e.kind + "\": t_s must be finite and >= 0");
    }
  }
  Transaction tx(db_);
  if (!db_.prepare("SELECT 1 FROM sessions WHERE id = ?").bind(1, session_id).step()) {
    throw NotFound("session " + std::to_string(session_id) + " does not exist");
  }
  db_.prepare("DELETE FROM session_events WHERE session_id = ?").bind(1, session_id).run();
  auto insert = db_.prepare(
      "INSERT INTO session_events (session_id, seq, t_s, kind, hand, label) "
      "VALUES (?, ?, ?, ?, ?, ?)");
  std::int64_t seq = 0;
  for (const SessionEvent& e : events) {
    insert.reset();
    insert.bind(1, session_id)
        .bind(2, seq++)
        .bind(3, e.t_s)
        .bind(4, e.kind)
        .bind(5, static_cast<std::int64_t>(e.hand))
        .bind(6, e.label)
        .run();
  }
  tx.commit();
}

std::vector<SessionEvent> SessionEventsRepo::list(std::int64_t session_id) {
  auto q = db_.prepare(
      "SELECT t_s, kind, hand, label FROM session_events WHERE session_id = ? ORDER BY seq");
  q.bind(1, session_id);
  std::vector<SessionEvent> out;
  while (q.step()) {
    out.push_back({q.real(0), q.text(1), static_cast<int>(q.int64(2)), q.text(3)});
  }
  return out;
}

}  // namespace incise::db
