#include "server/api/json_views.h"

#include "server/time_text.h"

namespace incise::server {

namespace {
nlohmann::json optional_time(const std::optional<std::int64_t>& t) {
  return t ? nlohmann::json(format_utc(*t)) : nlohmann::json(nullptr);
}
}  // namespace

nlohmann::json to_json(const db::User& user) {
  return {{"id", user.id},
          {"username", user.username},
          {"display_name", user.display_name},
          {"role", db::to_string(user.role)},
          {"disabled", user.disabled_at.has_value()},
          {"must_change_password", user.must_change_password}};
}

nlohmann::json to_json(const db::Station& station, bool online) {
  return {{"id", station.id},     {"name", station.name},         {"location", station.location},
          {"kind", station.kind}, {"retired", station.retired()}, {"online", online}};
}

nlohmann::json to_json(const db::Booking& b) {
  return {{"id", b.id},
          {"station_id", b.station_id},
          {"station_name", b.station_name},
          {"user_id", b.user_id},
          {"username", b.username},
          {"starts_at", format_utc(b.starts_at)},
          {"ends_at", format_utc(b.ends_at)},
          {"status", b.status},
          {"created_at", format_utc(b.created_at)}};
}

nlohmann::json to_json(const db::SessionRecord& s) {
  return {{"id", s.id},
          {"trainee_id", s.trainee_id},
          {"trainee", s.trainee},
          {"station_id", s.station_id ? nlohmann::json(*s.station_id) : nlohmann::json(nullptr)},
          {"station", s.station},
          {"task", s.task},
          {"state", s.state},
          {"started_at", optional_time(s.started_at)},
          {"ended_at", optional_time(s.ended_at)}};
}

nlohmann::json to_json(const db::RecordingRecord& r) {
  return {{"id", r.id},     {"session_id", r.session_id}, {"trainee", r.trainee},
          {"task", r.task}, {"duration_s", r.duration_s}, {"created_at", format_utc(r.created_at)}};
}

nlohmann::json to_json(const db::ScoreRecord& s) {
  nlohmann::json out = {{"id", s.id},
                        {"session_id", s.session_id},
                        {"trainee", s.trainee},
                        {"task", s.task},
                        {"metric", s.metric},
                        {"value", s.value},
                        {"unit", s.unit},
                        {"passed", s.passed},
                        {"created_at", format_utc(s.created_at)},
                        {"criterion", s.criterion},
                        {"threshold", nullptr}};
  // What it was judged against when it was stored; null for scores stored before thresholds were.
  if (!s.threshold_op.empty())
    out["threshold"] = {{"op", s.threshold_op}, {"value", s.threshold_value}};
  return out;
}

nlohmann::json to_json(const db::CurriculumRecord& c) {
  return {{"id", c.id},
          {"name", c.name},
          {"definition", nlohmann::json::parse(c.definition_json, nullptr, false)}};
}

}  // namespace incise::server
