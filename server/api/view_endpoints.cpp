#include "server/api/view_endpoints.h"

#include <charconv>
#include <iostream>
#include <mutex>

#include "db/recordings_repo.h"
#include "db/training_repo.h"
#include "server/api/api_error.h"
#include "server/api/live_access.h"
#include "server/api/router.h"
#include "server/live/frame_streamer.h"
#include "server/live/scene_library.h"
#include "server/live/scoring.h"
#include "server/live/session_scene.h"
#include "sim/io/scene_json.h"

namespace incise::server {
namespace {

// "/api/sessions/7/view" -> 7 with prefix "/api/sessions/" and suffix "/view"; 0 if no match.
std::int64_t id_between(std::string_view path, std::string_view prefix, std::string_view suffix) {
  if (!path.starts_with(prefix) || !path.ends_with(suffix) ||
      path.size() <= prefix.size() + suffix.size()) {
    return 0;
  }
  const auto digits = path.substr(prefix.size(), path.size() - prefix.size() - suffix.size());
  std::int64_t id = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), id);
  return ec == std::errc{} && end == digits.data() + digits.size() && id > 0 ? id : 0;
}

std::string_view path_of(std::string_view target) {
  return target.substr(0, target.find('?'));
}

ViewTarget live_target(ApiContext& ctx, std::int64_t session_id) {
  const auto& user = ctx.user();
  const auto record = db::TrainingRepo(ctx.db()).find_session(session_id);
  if (!record) throw ApiError(http::status::not_found, "no session " + std::to_string(session_id));
  api::check_session_access(ctx.db(), user, *record);
  auto session = ctx.app.live_sessions().find(session_id);
  if (!session) {
    throw ApiError(http::status::conflict, "session " + std::to_string(session_id) +
                                               " is not live (" + record->state +
                                               "); open its recording instead");
  }
  return {std::move(session), nullptr, api::may_look_outside(user), nullptr, {}, user.id};
}

// What a replay needs, read on a leased connection; the replay itself is built after it is back.
struct ReplayInput {
  std::string_view scene_id;
  std::string scene_text;  // with the recorded named material's constants, if it had one
  double tick_s = 0;
  std::vector<live::TickRecord> ticks;
  std::vector<render::MarkView> zones;  // the recorded task's visible zones
};

ReplayInput replay_input(ApiContext& ctx, std::int64_t recording_id) {
  const auto& user = ctx.user();
  auto& db = ctx.db();
  const auto meta = db::RecordingsRepo(db).find(recording_id);
  if (!meta) {
    throw ApiError(http::status::not_found, "no recording " + std::to_string(recording_id));
  }
  const auto record = db::TrainingRepo(db).find_session(meta->session_id);
  if (!record) throw ApiError(http::status::not_found, "recording without a session");
  api::check_session_access(db, user, *record);
  const auto name = "recording " + std::to_string(recording_id);
  if (meta->state != "complete") {
    throw ApiError(http::status::conflict, name + " is still being recorded");
  }
  if (meta->scene.empty()) {
    throw ApiError(http::status::conflict, name + " holds no recorded input (demo data)");
  }
  const auto scene = live::find_scene(meta->scene);
  if (!scene) {
    throw ApiError(http::status::conflict,
                   name + " needs scene \"" + meta->scene + "\", which this server does not have");
  }
  std::string text(scene->text);
  if (!meta->material.empty()) {
    text = api::scene_text_with_material(db, scene->id, scene->text, meta->material,
                                         http::status::conflict, name + " ran with ");
  }
  if (const auto refusal = live::replay_refusal(meta->scene, meta->scene_version, text);
      !refusal.empty()) {
    throw ApiError(http::status::conflict, name + " cannot be replayed: " + refusal);
  }
  auto ticks = live::load_tick_records(db, recording_id);
  if (ticks.empty()) throw ApiError(http::status::conflict, name + " is empty");
  const auto task = api::find_curriculum_task(db, record->task);
  return {scene->id, std::move(text), 1.0 / meta->tick_hz, std::move(ticks),
          task ? live::task_zones(*task) : std::vector<render::MarkView>{}};
}

}  // namespace

bool is_view_path(std::string_view target) {
  return id_between(path_of(target), "/api/sessions/", "/view") != 0 || is_replay_path(target);
}

bool is_replay_path(std::string_view target) {
  return id_between(path_of(target), "/api/recordings/", "/replay") != 0;
}

std::variant<ViewTarget, Response> resolve_view(const Request& request, AppState& app,
                                                const std::string& client) {
  const auto path = path_of(request.target());
  try {
    // The login cookie goes with any upgrade the browser makes, so a page of another origin must
    // not be able to open a trainee's stream with it.
    if (is_cross_origin(request)) {
      throw ApiError(http::status::forbidden, "cross-origin WebSocket refused");
    }
    std::optional<ReplayInput> input;
    bool outside_view_allowed = false;
    std::shared_ptr<void> slot;
    std::int64_t user_id = 0;
    {
      ApiContext ctx(request, app, Caller{client});
      if (const auto id = id_between(path, "/api/sessions/", "/view")) {
        return live_target(ctx, id);
      }
      const auto id = id_between(path, "/api/recordings/", "/replay");
      if (id == 0) {
        throw ApiError(http::status::not_found, "no WebSocket endpoint at " + std::string(path));
      }
      input = replay_input(ctx, id);
      outside_view_allowed = api::may_look_outside(ctx.user());
      user_id = ctx.user().id;
      std::string why;
      slot = app.replay_slots().take(ctx.user().id, why);
      if (!slot) {
        ViewTarget busy;
        busy.busy = std::move(why);
        return busy;
      }
    }
    // Building the engine takes a moment; other requests need not wait for it.
    return ViewTarget{nullptr,
                      std::make_unique<live::ReplaySession>(
                          live::load_session_scene(input->scene_id, input->scene_text),
                          input->tick_s, std::move(input->ticks), std::move(input->zones)),
                      outside_view_allowed,
                      std::move(slot),
                      {},
                      user_id};
  } catch (const ApiError& e) {
    return json_error(e.status(), e.what(), request.version(), false);
  } catch (const std::exception& e) {
    // Details go to the log, not to the client (as for the REST API).
    std::cerr << "incise-server: internal error on upgrade to " << path << ": " << e.what() << "\n";
    return json_error(http::status::internal_server_error, "internal server error",
                      request.version(), false);
  }
}

}  // namespace incise::server
