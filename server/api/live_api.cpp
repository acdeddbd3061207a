// Live sessions: start, inspect, pause, resume, stop (docs/api.md, "Live sessions").
#include <mutex>

#include "curriculum/curriculum_json.h"
#include "curriculum/station_offer.h"
#include "db/bookings_repo.h"
#include "db/curricula_repo.h"
#include "db/recordings_repo.h"
#include "db/reviews_repo.h"
#include "db/stations_repo.h"
#include "db/training_repo.h"
#include "db/transaction.h"
#include "devices/protocol.h"
#include "server/agent_session.h"
#include "server/api/api_error.h"
#include "server/api/audit_change.h"
#include "server/api/handlers.h"
#include "server/api/json_views.h"
#include "server/api/live_access.h"
#include "server/api/request_fields.h"
#include "server/live/scene_library.h"
#include "server/live/session_scene.h"
#include "sim/io/scene_json.h"
#include "sim/scene/scene_error.h"

namespace incise::server::api {

namespace {

constexpr double kTickHz = 500;

nlohmann::json live_json(const std::shared_ptr<live::LiveSession>& session) {
  if (!session) return nullptr;
  return {{"state", live::to_string(session->state())},
          {"reason", session->reason()},
          {"sim_time_s", session->sim_time_s()},
          {"agent_online", session->agent_online()},
          {"recording_id", session->recording_id()}};
}

ApiResponse session_response(ApiContext& ctx, std::int64_t session_id, const nlohmann::json& live,
                             http::status status = http::status::ok) {
  const auto record = db::TrainingRepo(ctx.db()).find_session(session_id);
  if (!record) throw ApiError(http::status::not_found, "no session " + std::to_string(session_id));
  auto out = to_json(*record);
  out["live"] = live;
  // The verdict by the progress rules, so that the browser shows it and computes none.
  const auto passed = session_passed(ctx.db(), *record);
  out["passed"] = passed ? nlohmann::json(*passed) : nlohmann::json(nullptr);
  return {status, out, {}};
}

// The live session behind the URL, for its owner, instructors and admins.
std::shared_ptr<live::LiveSession> controllable_session(ApiContext& ctx) {
  const auto record = visible_session(ctx);
  auto session = ctx.app.live_sessions().find(ctx.path_id);
  if (!session || session->state() == live::LiveState::finished) {
    throw ApiError(http::status::conflict, "session " + std::to_string(ctx.path_id) +
                                               " is not running (" + record.state + ")");
  }
  return session;
}

}  // namespace

ApiResponse start_session(ApiContext& ctx) {
  const auto& user = ctx.user();
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"station_id", "task", "expert"});
  const auto station_id = fields.integer("station_id");
  const auto task_key = fields.string("task");
  // Staff record expert runs for the task's benchmark (the experts' band beside every attempt).
  const bool expert = fields.has("expert") && fields.boolean("expert");
  if (expert && user.role == db::Role::trainee) {
    throw ApiError(http::status::forbidden, "expert runs are instructors' or admins'");
  }
  auto& db = ctx.db();
  const auto station = db::StationsRepo(db).find(station_id);
  if (!station) {
    throw ApiError(http::status::not_found, "no station " + std::to_string(station_id));
  }
  if (station->retired()) {
    throw ApiError(http::status::conflict, station->name + " is retired");
  }
  const auto plan = curriculum_with_task(db, task_key);
  if (!plan) throw ApiError(http::status::not_found, "no task \"" + task_key + "\"");
  const curriculum::Task* task = curriculum::find_task(*plan, task_key);
  // A task runs only at a station of the kind it needs (curriculum/station_offer.h).
  if (const auto misfit = curriculum::station_misfit(*task, station->name, station->kind);
      !misfit.empty()) {
    throw ApiError(http::status::conflict, misfit);
  }
  std::optional<std::int64_t> booking_id;
  if (user.role == db::Role::trainee) {
    // A trainee starts only what their progress has unlocked (curriculum/progress.h).
    const auto progress = curriculum::curriculum_progress(*plan, attempt_records(db, user.id));
    if (const auto* p = curriculum::find_progress(progress, task_key); p && !p->unlocked()) {
      throw ApiError(http::status::conflict, curriculum::locked_reason(*plan, *p));
    }
    const auto booking = db::BookingsRepo(db).covering(user.id, station_id, ctx.now);
    if (!booking) {
      throw ApiError(http::status::forbidden,
                     "no booking of station " + std::to_string(station_id) + " covers now");
    }
    booking_id = booking->id;
  }
  if (const auto busy = ctx.app.live_sessions().active_at(station_id)) {
    throw ApiError(http::status::conflict, "station " + std::to_string(station_id) +
                                               " is busy with session " +
                                               std::to_string(busy->session_id()));
  }
  // From here until add(): no other start may take the station.
  if (!ctx.app.live_sessions().claim(station_id)) {
    throw ApiError(http::status::conflict,
                   "station " + std::to_string(station_id) + " is busy with a session starting");
  }
  struct Claim {
    LiveSessions& sessions;
    std::int64_t station_id;
    bool held = true;
    ~Claim() {
      if (held) sessions.release_claim(station_id);
    }
  } claim{ctx.app.live_sessions(), station_id};
  if (!ctx.app.station_online(station_id)) {
    throw ApiError(http::status::conflict,
                   "station " + std::to_string(station_id) + " agent is offline");
  }
  const auto scene_source = live::find_scene(task->scene);
  if (!scene_source) {
    throw ApiError(http::status::unprocessable_entity, "task \"" + task_key + "\" needs scene \"" +
                                                           task->scene +
                                                           "\", which this server does not have");
  }

  // A task's named material (docs/calibration.md) replaces the scene's constants in its text.
  std::string scene_text(scene_source->text);
  if (!task->material.empty()) {
    scene_text = api::scene_text_with_material(db, scene_source->id, scene_source->text,
                                               task->material, http::status::unprocessable_entity,
                                               "task \"" + task_key + "\" names ");
  }
  live::LiveSessionParams params;
  try {
    params.scene = live::load_session_scene(scene_source->id, scene_text);
  } catch (const std::exception& e) {
    throw ApiError(http::status::unprocessable_entity,
                   "scene \"" + task->scene + "\" is invalid: " + e.what());
  }
  if (const auto mismatch = live::tools_mismatch(*params.scene, task->tools); !mismatch.empty()) {
    throw ApiError(http::status::unprocessable_entity,
                   "task \"" + task_key + "\" does not fit its scene: " + mismatch);
  }
  db::TrainingRepo training(db);
  db::Transaction tx(db);
  params.session_id = training.create_session(user.id, station_id, task_key, ctx.now, booking_id,
                                              ctx.app.config().node_id);
  training.set_session_state(params.session_id, "running", ctx.now);
  if (expert) {
    // Marked from the start: its scores join the benchmark when it finishes; an aborted run
    // has none and adds nothing.
    db::ReviewsRepo(db).set_expert_run(params.session_id, true, user.id, ctx.now);
    audit_change(db, user.id, "benchmark.add",
                 "session " + std::to_string(params.session_id) + " task " + task_key, ctx.now,
                 {{"expert_run", false}}, {{"expert_run", true}});
  }
  params.station_id = station_id;
  params.recording_id =
      db::RecordingsRepo(db).create(params.session_id, task->scene, live::scene_version(scene_text),
                                    0, kTickHz, ctx.now, task->material);
  tx.commit();
  params.task = *task;
  params.database = ctx.app.config().database;
  params.tick_hz = kTickHz;

  AppState* app = &ctx.app;
  const auto session_id = params.session_id;
  live::LiveSession::AgentLink link;
  link.send_force_model = [app, station_id](const devices::ForceModel& model) {
    if (auto agent = app->agent_for_station(station_id)) agent->send_force_model(model);
  };
  link.send_notice = [app, station_id, session_id](const char* state) {
    if (auto agent = app->agent_for_station(station_id)) {
      agent->send_text(devices::build_session_notice({session_id, state}));
    }
  };
  auto session = std::make_shared<live::LiveSession>(std::move(params), std::move(link));
  session->start();
  ctx.app.live_sessions().add(session);  // ends the claim
  claim.held = false;
  // The agent may have left between the check above and add(), when no session could hear it.
  session->set_agent_online(ctx.app.station_online(station_id));
  return session_response(ctx, session->session_id(), live_json(session), http::status::created);
}

ApiResponse get_session(ApiContext& ctx) {
  visible_session(ctx);
  return session_response(ctx, ctx.path_id, live_json(ctx.app.live_sessions().find(ctx.path_id)));
}

// The session thread records state changes too, a moment later; writing it here as well makes
// the response (and the next listing) agree with the session at once.
ApiResponse pause_session(ApiContext& ctx) {
  const auto session = controllable_session(ctx);
  if (const auto why = session->pause("paused by " + ctx.user().username); !why.empty()) {
    throw ApiError(http::status::conflict, why);
  }
  db::TrainingRepo(ctx.db()).set_session_state(ctx.path_id, "paused", ctx.now);
  return session_response(ctx, ctx.path_id, live_json(session));
}

ApiResponse resume_session(ApiContext& ctx) {
  const auto session = controllable_session(ctx);
  if (const auto why = session->resume(); !why.empty()) {
    throw ApiError(http::status::conflict, why);
  }
  db::TrainingRepo(ctx.db()).set_session_state(ctx.path_id, "running", ctx.now);
  return session_response(ctx, ctx.path_id, live_json(session));
}

ApiResponse stop_session(ApiContext& ctx) {
  const auto session = controllable_session(ctx);
  // Waits for the session thread to close the recording and store the score (on its own
  // database connection), without holding up every other request meanwhile.
  const auto who = ctx.user().username;
  session->stop("stopped by " + who);
  const auto live = live_json(session);
  ctx.app.live_sessions().remove(session->session_id());
  return session_response(ctx, ctx.path_id, live);
}

}  // namespace incise::server::api
