#include <algorithm>

#include "curriculum/curriculum_validation.h"
#include "curriculum/station_offer.h"
#include "db/bookings_repo.h"
#include "db/password.h"
#include "db/transaction.h"
#include "devices/protocol.h"
#include "devices/station_calibration.h"
#include "devices/station_calibration_json.h"
#include "server/agent_session.h"
#include "server/api/api_error.h"
#include "server/api/audit_change.h"
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
  // Linked here or to another node (docs/scale_out.md).
  const auto online = ctx.app.stations_online_anywhere(ctx.db());
  for (const auto& s : db::StationsRepo(ctx.db()).list()) {
    out.push_back(to_json(s, std::binary_search(online.begin(), online.end(), s.id)));
  }
  return {http::status::ok, out, {}};
}

ApiResponse create_station(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"name", "location", "kind"});
  const auto name = fields.text("name");
  if (name.empty() || name.size() > 64) {
    throw ApiError(http::status::unprocessable_entity, "name must be 1-64 characters");
  }
  const auto location = fields.text_or("location", "");
  if (location.size() > 120) {
    throw ApiError(http::status::unprocessable_entity, "location must be at most 120 characters");
  }
  const auto kind = station_kind(fields.string_or("kind", ""));
  const auto token = db::random_token();
  db::Transaction tx(ctx.db());  // the change and its audit entry, both or neither
  const auto station = db::StationsRepo(ctx.db()).create(name, location, token, ctx.now, kind);
  audit_change(ctx.db(), admin.id, "station.create", station.name, ctx.now, nullptr,
               to_json(station, false));
  tx.commit();
  return {http::status::created, {{"station", to_json(station, false)}, {"token", token}}, {}};
}

ApiResponse get_station_calibration(ApiContext& ctx) {
  ctx.require_role({db::Role::admin, db::Role::instructor});
  db::StationsRepo stations(ctx.db());
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
  db::StationsRepo stations(ctx.db());
  db::Transaction tx(ctx.db());  // "before", the change and its audit entry, no writer between
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
  const auto stored = stations.calibration(ctx.path_id);
  stations.set_calibration(ctx.path_id, text);
  audit_change(ctx.db(), admin.id, "station.calibrate", station->name, ctx.now,
               stored.empty() ? nlohmann::json{{"default", true}}
                              : nlohmann::json::parse(stored, nullptr, false),
               nlohmann::json::parse(text));
  tx.commit();
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

namespace {
// Why the station cannot be retired now ("" when it can): a running session, or bookings still
// ahead (their trainees must hear of it from a person, not find them gone).
std::string retire_refusal(ApiContext& ctx, const db::Station& station) {
  if (const auto session = ctx.app.live_sessions().active_at(station.id)) {
    return station.name + " is busy with session " + std::to_string(session->session_id()) +
           "; retire it when no session runs";
  }
  if (ctx.app.live_sessions().starting(station.id)) {
    return station.name + " is busy with a session starting; retire it when no session runs";
  }
  int ahead = 0;
  for (const auto& b : db::BookingsRepo(ctx.db()).station_schedule(station.id, ctx.now))
    ahead += b.ends_at > ctx.now ? 1 : 0;
  if (ahead > 0) {
    return station.name + " has " + std::to_string(ahead) + " booking" + (ahead == 1 ? "" : "s") +
           " ahead; cancel " + (ahead == 1 ? "it" : "them") + " before retiring it";
  }
  return "";
}
}  // namespace

ApiResponse update_station(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"kind", "retired"});
  if (!fields.has("kind") && !fields.has("retired")) {
    throw ApiError(http::status::unprocessable_entity, "send kind, retired or both");
  }
  auto& db = ctx.db();
  db::StationsRepo stations(db);
  // The checks, the change and its audit entry with no other writer between them: a booking made
  // meanwhile cannot slip past the retire check, nor a concurrent edit be written back stale.
  db::Transaction tx(db);
  const auto before = existing_station(stations, ctx.path_id);
  auto after = before;
  if (fields.has("kind")) after.kind = station_kind(fields.string("kind"));
  if (fields.has("retired") && fields.boolean("retired") != before.retired()) {
    after.retired_at = before.retired() ? std::nullopt : std::optional<std::int64_t>(ctx.now);
    if (after.retired()) {
      if (const auto why = retire_refusal(ctx, before); !why.empty())
        throw ApiError(http::status::conflict, why);
    }
  }
  const auto fields_of = [](const db::Station& s) {
    return nlohmann::json{{"kind", s.kind}, {"retired", s.retired()}};
  };
  if (fields_of(after) != fields_of(before)) {
    stations.set_kind(before.id, after.kind);
    stations.set_retired(before.id, after.retired_at);
    const char* action = after.retired() == before.retired() ? "station.update"
                         : after.retired()                   ? "station.retire"
                                                             : "station.reinstate";
    audit_change(db, admin.id, action, before.name, ctx.now, fields_of(before), fields_of(after));
  }
  tx.commit();
  // A retired station's agent is turned away (agent_session.cpp), the one connected now at once.
  if (after.retired() && !before.retired()) {
    if (const auto agent = ctx.app.agent_for_station(after.id)) agent->close("station retired");
  }
  return {http::status::ok, to_json(after, ctx.app.station_online_anywhere(db, after.id)), {}};
}

ApiResponse station_tasks(ApiContext& ctx) {
  const auto& user = ctx.user();
  auto& db = ctx.db();
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
          {{"station", to_json(station, ctx.app.station_online_anywhere(db, station.id))},
           {"tasks", std::move(tasks)}},
          {}};
}

}  // namespace incise::server::api
