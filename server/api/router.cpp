#include "server/api/router.h"

#include <array>
#include <charconv>
#include <iostream>
#include <mutex>

#include "db/db_error.h"
#include "server/api/api_error.h"
#include "server/api/handlers.h"
#include "server/wire_text.h"

namespace incise::server {

namespace {

// Long enough for any message of ours; a client's echoed bytes beyond it are cut.
constexpr std::size_t kMaxErrorMessageBytes = 512;

using Handler = ApiResponse (*)(ApiContext&);

struct Route {
  http::verb method;
  std::string_view pattern;  // "{id}" matches a positive integer segment
  Handler handler;
};

constexpr std::array kRoutes = {
    Route{http::verb::get, "/api/health", api::health},
    Route{http::verb::get, "/api/ready", api::ready},
    Route{http::verb::post, "/api/login", api::login},
    Route{http::verb::post, "/api/logout", api::logout},
    Route{http::verb::get, "/api/me", api::me},
    Route{http::verb::post, "/api/me/password", api::change_own_password},
    Route{http::verb::get, "/api/users", api::list_users},
    Route{http::verb::post, "/api/users", api::create_user},
    Route{http::verb::patch, "/api/users/{id}", api::update_user},
    Route{http::verb::post, "/api/users/{id}/password", api::reset_user_password},
    Route{http::verb::put, "/api/users/{id}/instructors", api::set_trainee_instructors},
    Route{http::verb::get, "/api/stations", api::list_stations},
    Route{http::verb::post, "/api/stations", api::create_station},
    Route{http::verb::patch, "/api/stations/{id}", api::update_station},
    Route{http::verb::get, "/api/stations/{id}/tasks", api::station_tasks},
    Route{http::verb::get, "/api/stations/{id}/calibration", api::get_station_calibration},
    Route{http::verb::put, "/api/stations/{id}/calibration", api::put_station_calibration},
    Route{http::verb::get, "/api/stations/{id}/schedule", api::station_schedule},
    Route{http::verb::get, "/api/bookings", api::list_bookings},
    Route{http::verb::post, "/api/bookings", api::create_booking},
    Route{http::verb::delete_, "/api/bookings/{id}", api::cancel_booking},
    Route{http::verb::get, "/api/sessions", api::list_sessions},
    Route{http::verb::post, "/api/sessions", api::start_session},
    Route{http::verb::get, "/api/sessions/{id}", api::get_session},
    Route{http::verb::post, "/api/sessions/{id}/pause", api::pause_session},
    Route{http::verb::post, "/api/sessions/{id}/resume", api::resume_session},
    Route{http::verb::post, "/api/sessions/{id}/stop", api::stop_session},
    Route{http::verb::get, "/api/sessions/{id}/annotations", api::list_annotations},
    Route{http::verb::post, "/api/sessions/{id}/annotations", api::add_annotation},
    Route{http::verb::get, "/api/sessions/{id}/adjustments", api::list_adjustments},
    Route{http::verb::post, "/api/sessions/{id}/adjustments", api::adjust_score},
    Route{http::verb::get, "/api/sessions/{id}/review", api::session_review},
    Route{http::verb::put, "/api/sessions/{id}/expert", api::set_expert_run},
    Route{http::verb::get, "/api/benchmarks", api::list_benchmarks},
    Route{http::verb::get, "/api/recordings", api::list_recordings},
    Route{http::verb::get, "/api/scores", api::list_scores},
    Route{http::verb::get, "/api/exports/scores.csv", api::export_scores_csv},
    Route{http::verb::get, "/api/audit", api::list_audit},
    Route{http::verb::get, "/api/progress", api::my_progress},
    Route{http::verb::get, "/api/trainees/{id}/progress", api::trainee_progress},
    Route{http::verb::get, "/api/trainees/progress", api::progress_overview},
    Route{http::verb::get, "/api/metrics", api::list_metrics},
    Route{http::verb::get, "/api/curricula", api::list_curricula},
    Route{http::verb::post, "/api/curricula", api::import_curriculum},
    Route{http::verb::put, "/api/curricula/{id}", api::update_curriculum},
    Route{http::verb::get, "/api/curricula/{id}/export", api::export_curriculum},
    Route{http::verb::get, "/api/calibration/scenes", api::list_calibration_scenes},
    Route{http::verb::get, "/api/calibration/example", api::calibration_example},
    Route{http::verb::get, "/api/calibration/jobs", api::list_calibration_jobs},
    Route{http::verb::post, "/api/calibration/jobs", api::create_calibration_job},
    Route{http::verb::get, "/api/calibration/jobs/{id}", api::get_calibration_job},
    Route{http::verb::post, "/api/calibration/jobs/{id}/cancel", api::cancel_calibration_job},
    Route{http::verb::get, "/api/materials", api::list_materials},
    Route{http::verb::post, "/api/materials", api::create_material},
};

// Matches `path` against `pattern` segment by segment; fills `id` for "{id}".
bool matches(std::string_view pattern, std::string_view path, std::int64_t& id) {
  while (!pattern.empty() || !path.empty()) {
    if (pattern.empty() || path.empty() || pattern[0] != '/' || path[0] != '/') return false;
    pattern.remove_prefix(1);
    path.remove_prefix(1);
    const auto pe = std::min(pattern.find('/'), pattern.size());
    const auto se = std::min(path.find('/'), path.size());
    const auto pseg = pattern.substr(0, pe);
    const auto seg = path.substr(0, se);
    if (pseg == "{id}") {
      auto [end, ec] = std::from_chars(seg.data(), seg.data() + seg.size(), id);
      if (ec != std::errc{} || end != seg.data() + seg.size() || id <= 0) return false;
    } else if (pseg != seg) {
      return false;
    }
    pattern.remove_prefix(pe);
    path.remove_prefix(se);
  }
  return true;
}

bool is_state_changing(http::verb v) {
  return v == http::verb::post || v == http::verb::put || v == http::verb::patch ||
         v == http::verb::delete_;
}

// CSRF defence (docs/api.md): state-changing requests must be JSON (a cross-site form cannot send
// that without a preflight, which this server never grants) and must not come from another origin.
void check_csrf(const Request& req) {
  if (!is_state_changing(req.method())) return;
  if (is_cross_origin(req)) throw ApiError(http::status::forbidden, "cross-origin request refused");
  if (req.method() == http::verb::delete_ && req.body().empty()) return;
  if (!is_json_media_type(req[http::field::content_type])) {
    throw ApiError(http::status::bad_request, "Content-Type must be application/json");
  }
}

ApiResponse dispatch(ApiContext& ctx, std::string_view path) {
  bool path_known = false;
  for (const auto& route : kRoutes) {
    std::int64_t id = 0;
    if (!matches(route.pattern, path, id)) continue;
    path_known = true;
    if (route.method != ctx.request.method()) continue;
    ctx.path_id = id;
    check_csrf(ctx.request);
    return route.handler(ctx);
  }
  if (path_known) {
    throw ApiError(http::status::method_not_allowed, std::string(ctx.request.method_string()) +
                                                         " is not allowed on " + std::string(path));
  }
  throw ApiError(
      http::status::not_found,
      "no such endpoint: " + std::string(ctx.request.method_string()) + " " + std::string(path));
}

}  // namespace

bool is_json_media_type(std::string_view content_type) {
  // The media type is what precedes any parameters ("; charset=utf-8"), case-insensitive (RFC
  // 9110 section 8.3.1): "application/json", never "application/jsonx".
  auto type = content_type.substr(0, content_type.find(';'));
  while (!type.empty() && (type.back() == ' ' || type.back() == '\t'))
    type.remove_suffix(1);
  constexpr std::string_view kJson = "application/json";
  if (type.size() != kJson.size()) return false;
  for (std::size_t i = 0; i < type.size(); ++i) {
    const char c =
        type[i] >= 'A' && type[i] <= 'Z' ? static_cast<char>(type[i] - 'A' + 'a') : type[i];
    if (c != kJson[i]) return false;
  }
  return true;
}

bool is_cross_origin(const Request& req) {
  const auto origin = req[http::field::origin];
  if (origin.empty()) return false;
  const auto host = req[http::field::host];
  // A page of this server: http or https (behind a TLS proxy) and this host. Anything else, "null"
  // (a sandboxed frame, a file) and other schemes among it, is another origin.
  for (const std::string_view scheme : {"http://", "https://"}) {
    if (origin.starts_with(scheme)) return origin.substr(scheme.size()) != host;
  }
  return true;
}

Response json_error(http::status status, std::string_view message, unsigned version,
                    bool keep_alive) {
  Response res{status, version};
  res.set(http::field::content_type, "application/json");
  res.set(http::field::cache_control, "no-store");
  res.keep_alive(keep_alive);
  try {
    // The message may echo what the client sent (a path, a parser's excerpt of the body).
    res.body() = dump_json({{"error", clip_utf8(message, kMaxErrorMessageBytes)}});
  } catch (...) {
    // Only an allocation can fail above; the error path must still answer.
    res.body() = R"({"error":"internal server error"})";
  }
  res.prepare_payload();
  return res;
}

Response handle_api_request(const Request& request, AppState& app, const Caller& caller) {
  const auto target = request.target();
  const auto path = target.substr(0, target.find('?'));
  const auto version = request.version();
  const bool keep_alive = request.keep_alive();
  try {
    ApiContext ctx(request, app, caller);
    const ApiResponse out = dispatch(ctx, std::string_view(path.data(), path.size()));
    Response res{out.status, version};
    res.set(http::field::cache_control, "no-store");
    for (const auto& [name, value] : out.headers)
      res.insert(name, value);
    if (out.text_body) {
      res.set(http::field::content_type, out.content_type);
      res.body() = *out.text_body;
    } else if (out.status != http::status::no_content) {
      res.set(http::field::content_type, "application/json");
      res.body() = dump_json(out.body);
    }
    res.keep_alive(keep_alive);
    res.prepare_payload();
    return res;
  } catch (const ApiError& e) {
    auto res = json_error(e.status(), e.what(), version, keep_alive);
    for (const auto& [name, value] : e.headers())
      res.set(name, value);
    return res;
  } catch (const db::Conflict& e) {
    return json_error(http::status::conflict, e.what(), version, keep_alive);
  } catch (const db::NotFound& e) {
    return json_error(http::status::not_found, e.what(), version, keep_alive);
  } catch (const std::exception& e) {
    // Details go to the log, not to the client.
    std::cerr << "incise-server: internal error on " << request.method_string() << " " << path
              << ": " << e.what() << "\n";
    return json_error(http::status::internal_server_error, "internal server error", version,
                      keep_alive);
  }
}

}  // namespace incise::server
