#include "db/reviews_repo.h"

#include <string>

#include "db/statement.h"

namespace incise::db {
namespace {

// The columns read_adjustment reads, with the author's username.
constexpr const char* kAdjustmentSelect =
    "SELECT s.id, s.session_id, s.author_id, u.username, s.passed, s.reason, s.created_at "
    "FROM score_adjustments s JOIN users u ON u.id = s.author_id ";

ScoreAdjustment read_adjustment(Statement& q) {
  return {q.int64(0), q.int64(1), q.int64(2), q.text(3), q.int64(4) != 0, q.text(5), q.int64(6)};
}

// The columns read_annotation reads, with the author's username.
constexpr const char* kAnnotationSelect =
    "SELECT a.id, a.session_id, a.author_id, u.username, a.t_s, a.text, a.created_at "
    "FROM annotations a JOIN users u ON u.id = a.author_id ";

Annotation read_annotation(Statement& q) {
  return {q.int64(0), q.int64(1), q.int64(2), q.text(3), q.real(4), q.text(5), q.int64(6)};
}

}  // namespace

Annotation ReviewsRepo::add_annotation(std::int64_t session_id, std::int64_t author_id, double t_s,
                                       const std::string& text, std::int64_t now) {
  const std::int64_t id =
      db_.prepare(
             "INSERT INTO annotations (session_id, author_id, t_s, text, created_at) "
             "VALUES (?, ?, ?, ?, ?) RETURNING id")
          .bind(1, session_id)
          .bind(2, author_id)
          .bind(3, t_s)
          .bind(4, text)
          .bind(5, now)
          .insert();
  auto q = db_.prepare(std::string(kAnnotationSelect) + "WHERE a.id = ?");
  q.bind(1, id).step();
  return read_annotation(q);
}

std::vector<Annotation> ReviewsRepo::annotations(std::int64_t session_id) {
  auto q =
      db_.prepare(std::string(kAnnotationSelect) + "WHERE a.session_id = ? ORDER BY a.t_s, a.id");
  q.bind(1, session_id);
  std::vector<Annotation> out;
  while (q.step())
    out.push_back(read_annotation(q));
  return out;
}

ScoreAdjustment ReviewsRepo::adjust(std::int64_t session_id, std::int64_t author_id, bool passed,
                                    const std::string& reason, std::int64_t now) {
  const std::int64_t id =
      db_.prepare(
             "INSERT INTO score_adjustments (session_id, author_id, passed, reason, created_at) "
             "VALUES (?, ?, ?, ?, ?) RETURNING id")
          .bind(1, session_id)
          .bind(2, author_id)
          .bind(3, passed ? 1 : 0)
          .bind(4, reason)
          .bind(5, now)
          .insert();
  auto q = db_.prepare(std::string(kAdjustmentSelect) + "WHERE s.id = ?");
  q.bind(1, id).step();
  return read_adjustment(q);
}

std::vector<ScoreAdjustment> ReviewsRepo::adjustments(std::int64_t session_id) {
  auto q = db_.prepare(std::string(kAdjustmentSelect) + "WHERE s.session_id = ? ORDER BY s.id");
  q.bind(1, session_id);
  std::vector<ScoreAdjustment> out;
  while (q.step())
    out.push_back(read_adjustment(q));
  return out;
}

std::vector<ScoreAdjustment> ReviewsRepo::latest_adjustments(std::int64_t trainee_id) {
  auto q = db_.prepare(std::string(kAdjustmentSelect) +
                       "JOIN sessions se ON se.id = s.session_id "
                       "WHERE se.trainee_id = ? AND s.id = (SELECT MAX(id) FROM score_adjustments "
                       "WHERE session_id = s.session_id) ORDER BY s.session_id");
  q.bind(1, trainee_id);
  std::vector<ScoreAdjustment> out;
  while (q.step())
    out.push_back(read_adjustment(q));
  return out;
}

void ReviewsRepo::set_expert_run(std::int64_t session_id, bool expert, std::int64_t by,
                                 std::int64_t now) {
  if (expert) {
    db_.prepare(
           "INSERT INTO expert_runs (session_id, marked_by, marked_at) VALUES (?, ?, ?) ON "
           "CONFLICT "
           "DO NOTHING")
        .bind(1, session_id)
        .bind(2, by)
        .bind(3, now)
        .run();
  } else {
    db_.prepare("DELETE FROM expert_runs WHERE session_id = ?").bind(1, session_id).run();
  }
}

bool ReviewsRepo::is_expert_run(std::int64_t session_id) {
  auto q = db_.prepare("SELECT 1 FROM expert_runs WHERE session_id = ?");
  q.bind(1, session_id);
  return q.step();
}

std::vector<ExpertScore> ReviewsRepo::expert_scores() {
  auto q = db_.prepare(
      "SELECT sc.session_id, se.task, sc.metric, sc.unit, sc.value FROM expert_runs e "
      "JOIN sessions se ON se.id = e.session_id JOIN scores sc ON sc.session_id = e.session_id "
      "ORDER BY se.task, sc.metric, sc.session_id");
  std::vector<ExpertScore> out;
  while (q.step())
    out.push_back({q.int64(0), q.text(1), q.text(2), q.text(3), q.real(4)});
  return out;
}

}  // namespace incise::db
