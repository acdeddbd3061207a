#include "db/audit_repo.h"
#include "db/password.h"
#include "server/api/api_error.h"
#include "server/api/handlers.h"
#include "server/api/json_views.h"
#include "server/api/request_fields.h"

namespace incise::server::api {

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
  const RequestFields fields(body, {"name", "location"});
  const auto name = fields.string("name");
  if (name.empty() || name.size() > 64) {
    throw ApiError(http::status::unprocessable_entity, "name must be 1-64 characters");
  }
  const auto location = fields.string_or("location", "");
  if (location.size() > 120) {
    throw ApiError(http::status::unprocessable_entity, "location must be at most 120 characters");
  }
  const auto token = db::random_token();
  const auto station = db::StationsRepo(ctx.app.db()).create(name, location, token, ctx.now);
  db::AuditRepo(ctx.app.db()).record(admin.id, "station.create", station.name, ctx.now);
  return {http::status::created, {{"station", to_json(station, false)}, {"token", token}}, {}};
}

}  // namespace incise::server::api
