#include "curriculum/curriculum_validation.h"
#include "curriculum/station_offer.h"
#include "db/audit_repo.h"
#include "db/password.h"
#include "devices/protocol.h"
#include "devices/station_calibration.h"
#include "devices/station_calibration_json.h"
#include "server/agent_session.h"
#include "server/api/api_error.h"
#include "server/api/handlers.h"
#include "server/api/json_views.h"
#include "server/api/live_access.h"
#include "server/api/request_fields.h"

namespace incise::server::api {

using devices::ParseResult;

namespace {

// A station kind as sent: "" (none declared) or a key like a task's station_kind.
std::string station_kind(std::string kind) {
  if (!kind.empty() && (kind.size() > 32 || !curriculum::is_valid_key(kind))) {
    throw ApiError(http::status::unprocessable_entity,
                   "kind must be empty or a key of at most 32 characters: a lowercase letter, then "
                   "lowercase letters, digits or '_' (e.g. \"laparoscopy\")");
  }
  return kind;
}

db::Station existing_station(db::StationsRepo& stations, std::int64_t id) {
  auto station = stations.find(id);
  if (!station) {
    throw ApiError(http::status::not_found, "station " + std::to_string(id) + " does not exist");
  }
  return *station;
}

}  // namespace

ApiResponse list_stations(ApiContext& ctx) {
  ctx.user();
  auto out = nlohmann::json::array();
  for (const auto& s : db::StationsRepo(ctx.app.db()).list()) {
    out.push_back(to_json(s, ctx.app.station_online(s.id)));
  }
  return {http::status::ok, out, {}};
}

ApiResponse create_station(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"name", "location", "kind"});
  const auto name = fields.string("name");
  if (name.empty() || name.size() > 64) {
    throw ApiError(http::status::unprocessable_entity, "name must be 1-64 characters");
  }
  const auto location = fields.string_or("location", "");
  if (location.size() > 120) {
    throw ApiError(http::status::unprocessable_entity, "location must be at most 120 characters");
  }
  const auto kind = station_kind(fields.string_or("kind", ""));
  const auto token = db::random_token();
  const auto station = db::StationsRepo(ctx.app.db()).create(name, location, token, ctx.now, kind);
  db::AuditRepo(ctx.app.db()).record(admin.id, "station.create", station.name, ctx.now);
  return {http::status::created, {{"station", to_json(station, false)}, {"token", token}}, {}};
}

ApiResponse get_station_calibration(ApiContext& ctx) {
  ctx.require_role({db::Role::admin, db::Role::instructor});
  db::StationsRepo stations(ctx.app.db());
  if (!stations.find(ctx.path_id)) {
    throw ApiError(http::status::not_found,
                   "station " + std::to_string(ctx.path_id) + " does not exist");
  }
  const auto stored = stations.calibration(ctx.path_id);
  auto parsed = stored.empty() ? ParseResult<devices::StationCalibration>::success(
                                     devices::default_station_calibration())
                               : devices::parse_station_calibration(stored);
  if (!parsed) {
    throw ApiError(http::status::internal_server_error, "the stored calibration of station " +
                                                            std::to_string(ctx.path_id) +
                                                            " is invalid: " + parsed.error);
  }
  const auto& calibration = *parsed.value;
  return {http::status::ok,
          {{"station_id", ctx.path_id},
           {"default", stored.empty()},
           {"calibration", nlohmann::json::parse(devices::station_calibration_json(calibration))}},
          {}};
}

ApiResponse put_station_calibration(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto body = ctx.json_body();
  const auto parsed = devices::parse_station_calibration(body.dump());
  if (!parsed) throw ApiError(http::status::unprocessable_entity, parsed.error);
  // Stored normalised (unit quaternions, full precision), so every reader sees the same text.
  const auto text = devices::station_calibration_json(*parsed.value);
  db::StationsRepo stations(ctx.app.db());
  const auto station = stations.find(ctx.path_id);
  if (!station) {
    throw ApiError(http::status::not_found,
                   "station " + std::to_string(ctx.path_id) + " does not exist");
  }
  // Remapping a hand that is touching tissue would move its tool in the scene at once.
  if (const auto session = ctx.app.live_sessions().active_at(ctx.path_id)) {
    throw ApiError(http::status::conflict, "station " + std::to_string(ctx.path_id) +
                                               " is busy with session " +
                                               std::to_string(session->session_id()) +
                                               "; change its calibration when no session runs");
  }
  stations.set_calibration(ctx.path_id, text);
  db::AuditRepo(ctx.app.db()).record(admin.id, "station.calibrate", station->name, ctx.now);
  // A connected agent applies it at once.
  if (const auto agent = ctx.app.agent_for_station(ctx.path_id)) {
    agent->send_text(devices::build_calibration_notice(text));
  }
  return {http::status::ok,
          {{"station_id", ctx.path_id},
           {"default", false},
           {"calibration", nlohmann::json::parse(text)}},
          {}};
}

ApiResponse update_station(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"kind"});
  const auto kind = station_kind(fields.string("kind"));
  db::StationsRepo stations(ctx.app.db());
  const auto before = existing_station(stations, ctx.path_id);
  stations.set_kind(ctx.path_id, kind);
  db::AuditRepo(ctx.app.db())
      .record(admin.id, "station.update",
              before.name + ": kind \"" + before.kind + "\" -> \"" + kind + "\"", ctx.now);
  auto after = before;
  after.kind = kind;
  return {http::status::ok, to_json(after, ctx.app.station_online(after.id)), {}};
}

ApiResponse station_tasks(ApiContext& ctx) {
  const auto& user = ctx.user();
  auto& db = ctx.app.db();
  db::StationsRepo stations(db);
  const auto station = existing_station(stations, ctx.path_id);
  auto tasks = nlohmann::json::array();
  if (const auto plan = session_curriculum(db)) {
    std::optional<std::vector<curriculum::TaskProgress>> progress;
    if (user.role == db::Role::trainee)
      progress = curriculum::curriculum_progress(*plan, attempt_records(db, user.id));
    for (const auto& offer :
         curriculum::station_offer(*plan, station.kind, progress ? &*progress : nullptr)) {
      tasks.push_back({{"key", offer.task->key},
                       {"name", offer.task->name},
                       {"module", offer.module},
                       {"instructions", offer.task->instructions},
                       {"locked_reason", offer.locked_reason}});
    }
  }
  return {http::status::ok,
          {{"station", to_json(station, ctx.app.station_online(station.id))},
           {"tasks", std::move(tasks)}},
          {}};
}

}  // namespace incise::server::api
