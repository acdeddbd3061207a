// Instructor review of an attempt: time-stamped annotations on its recording and
// score adjustments with a reason (audited). The session's trainee, instructors and admins read
// them; instructors and admins write them.

#include <cmath>

#include "db/recordings_repo.h"
#include "db/reviews_repo.h"
#include "db/training_repo.h"
#include "db/transaction.h"
#include "server/api/api_error.h"
#include "server/api/audit_change.h"
#include "server/api/handlers.h"
#include "server/api/live_access.h"
#include "server/api/request_fields.h"
#include "server/time_text.h"

namespace incise::server::api {
namespace {

constexpr std::size_t kMaxAnnotation = 2000;
constexpr std::size_t kMaxReason = 500;

nlohmann::json to_json(const db::Annotation& a) {
  return {{"id", a.id},         {"session_id", a.session_id},
          {"author", a.author}, {"t_s", a.t_s},
          {"text", a.text},     {"created_at", format_utc(a.created_at)}};
}

nlohmann::json to_json(const db::ScoreAdjustment& s) {
  return {{"id", s.id},         {"session_id", s.session_id},
          {"author", s.author}, {"passed", s.passed},
          {"reason", s.reason}, {"created_at", format_utc(s.created_at)}};
}

}  // namespace

ApiResponse list_annotations(ApiContext& ctx) {
  const auto session = visible_session(ctx);
  auto out = nlohmann::json::array();
  for (const auto& a : db::ReviewsRepo(ctx.db()).annotations(session.id))
    out.push_back(to_json(a));
  return {http::status::ok, std::move(out)};
}

ApiResponse add_annotation(ApiContext& ctx) {
  const auto& author = ctx.require_role({db::Role::instructor, db::Role::admin});
  const auto session = visible_session(ctx);
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"t_s", "text"});
  const double t_s = fields.number("t_s");
  const auto text = fields.text("text", true);
  // Within the recording: 0 .. its duration (a live session's grows; its end is now).
  const auto recording = db::RecordingsRepo(ctx.db()).find_by_session(session.id);
  const double duration = recording ? recording->duration_s : 0.0;
  if (!std::isfinite(t_s) || t_s < 0 ||
      (recording && recording->state == "complete" && t_s > duration)) {
    throw ApiError(http::status::unprocessable_entity,
                   "t_s must be within the recording, 0 to " + std::to_string(duration) + " s");
  }
  if (text.empty() || text.size() > kMaxAnnotation) {
    throw ApiError(http::status::unprocessable_entity,
                   "text must be 1-" + std::to_string(kMaxAnnotation) + " characters");
  }
  const auto annotation =
      db::ReviewsRepo(ctx.db()).add_annotation(session.id, author.id, t_s, text, ctx.now);
  return {http::status::created, to_json(annotation)};
}

ApiResponse list_adjustments(ApiContext& ctx) {
  const auto session = visible_session(ctx);
  auto out = nlohmann::json::array();
  for (const auto& s : db::ReviewsRepo(ctx.db()).adjustments(session.id))
    out.push_back(to_json(s));
  return {http::status::ok, std::move(out)};
}

ApiResponse adjust_score(ApiContext& ctx) {
  const auto& author = ctx.require_role({db::Role::instructor, db::Role::admin});
  const auto session = visible_session(ctx);
  if (session.trainee_id == author.id && author.role != db::Role::admin) {
    throw ApiError(http::status::forbidden, "you cannot adjust the score of your own attempt");
  }
  if (session.state != "finished") {
    throw ApiError(http::status::conflict, "session " + std::to_string(session.id) + " is " +
                                               session.state +
                                               ": only a finished attempt is scored");
  }
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"passed", "reason"});
  const bool passed = fields.boolean("passed");
  const auto reason = fields.text("reason", true);
  if (reason.size() < 3 || reason.size() > kMaxReason) {
    throw ApiError(http::status::unprocessable_entity,
                   "reason must be 3-" + std::to_string(kMaxReason) + " characters");
  }
  db::Transaction tx(ctx.db());  // the adjustment and its audit entry, both or neither
  const auto adjustment =
      db::ReviewsRepo(ctx.db()).adjust(session.id, author.id, passed, reason, ctx.now);
  audit_change(
      ctx.db(), author.id, "score.adjust",
      "session " + std::to_string(session.id) + (passed ? " passed: " : " not passed: ") + reason,
      ctx.now, nullptr, {{"session_id", session.id}, {"passed", passed}, {"reason", reason}});
  tx.commit();
  return {http::status::created, to_json(adjustment)};
}

}  // namespace incise::server::api
