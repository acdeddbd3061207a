#include <cstdio>
#include <string>
#include <string_view>

#include "curriculum/curriculum_error.h"
#include "curriculum/curriculum_json.h"
#include "curriculum/metric_catalogue.h"
#include "db/audit_repo.h"
#include "db/calibration_repo.h"
#include "db/curricula_repo.h"
#include "db/training_repo.h"
#include "db/transaction.h"
#include "server/api/api_error.h"
#include "server/api/audit_change.h"
#include "server/api/handlers.h"
#include "server/api/json_views.h"
#include "server/api/live_access.h"
#include "server/live/scene_library.h"
#include "server/time_text.h"

namespace incise::server::api {

namespace {
// Trainees see only their own records, instructors their own and their trainees', admins
// everyone's.
db::TraineeScope visible_trainee(ApiContext& ctx) {
  return visible_scope(ctx.user());
}

template <class Records>
ApiResponse as_list(const Records& records) {
  auto out = nlohmann::json::array();
  for (const auto& r : records)
    out.push_back(to_json(r));
  return {http::status::ok, out, {}};
}
}  // namespace

ApiResponse list_sessions(ApiContext& ctx) {
  return as_list(db::TrainingRepo(ctx.db()).sessions(visible_trainee(ctx)));
}

ApiResponse list_recordings(ApiContext& ctx) {
  return as_list(db::TrainingRepo(ctx.db()).recordings(visible_trainee(ctx)));
}

ApiResponse list_scores(ApiContext& ctx) {
  return as_list(db::TrainingRepo(ctx.db()).scores(visible_trainee(ctx)));
}

namespace {

// One CSV field (RFC 4180): quoted when it holds a comma, a quote or a line break, quotes
// doubled. A text field a spreadsheet would read as a formula (=, +, -, @, tab, CR first) gets a
// leading apostrophe, so that an export opened in a spreadsheet never runs a trainee's name.
std::string csv_text(const std::string& text) {
  std::string field = text;
  if (!field.empty() &&
      std::string_view("=+-@\t\r").find(field.front()) != std::string_view::npos) {
    field.insert(field.begin(), '\'');
  }
  if (field.find_first_of(",\"\r\n") == std::string::npos) return field;
  std::string quoted = "\"";
  for (const char c : field) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

std::string csv_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

}  // namespace

ApiResponse export_scores_csv(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  std::string csv = "score_id,session_id,trainee,task,metric,value,unit,passed,created_at\r\n";
  const auto scores = db::TrainingRepo(ctx.db()).scores();
  for (const auto& s : scores) {
    csv += std::to_string(s.id) + "," + std::to_string(s.session_id) + "," + csv_text(s.trainee) +
           "," + csv_text(s.task) + "," + csv_text(s.metric) + "," + csv_number(s.value) + "," +
           csv_text(s.unit) + "," + (s.passed ? "true" : "false") + "," + format_utc(s.created_at) +
           "\r\n";
  }
  db::AuditRepo(ctx.db()).record(admin.id, "export.scores", std::to_string(scores.size()) + " rows",
                                 ctx.now);
  ApiResponse out;
  out.text_body = std::move(csv);
  out.content_type = "text/csv; charset=utf-8";
  out.headers = {{"Content-Disposition", "attachment; filename=\"incise-scores.csv\""}};
  return out;
}

namespace {
// A stored before/after (JSON object text, "" for none) for the response; never throws.
nlohmann::json audit_fields(const std::string& text) {
  if (text.empty()) return nullptr;
  auto value = nlohmann::json::parse(text, nullptr, false);
  return value.is_discarded() ? nlohmann::json(text) : value;
}
}  // namespace

ApiResponse list_audit(ApiContext& ctx) {
  ctx.require_role({db::Role::admin});
  auto out = nlohmann::json::array();
  for (const auto& e : db::AuditRepo(ctx.db()).list()) {
    out.push_back({{"id", e.id},
                   {"at", format_utc(e.at)},
                   {"user_id", e.user_id ? nlohmann::json(*e.user_id) : nlohmann::json(nullptr)},
                   {"action", e.action},
                   {"detail", e.detail},
                   {"before", audit_fields(e.before_json)},
                   {"after", audit_fields(e.after_json)}});
  }
  return {http::status::ok, std::move(out)};
}

namespace {

// The request body as a validated curriculum, or a 422 naming the path of the first problem.
curriculum::Curriculum curriculum_of(ApiContext& ctx) {
  curriculum::Curriculum plan;
  try {
    plan = curriculum::parse_curriculum(ctx.json_body());
  } catch (const curriculum::CurriculumError& e) {
    throw ApiError(http::status::unprocessable_entity, e.what());
  }
  // A task's named material must exist and fit its scene (docs/calibration.md).
  for (std::size_t m = 0; m < plan.modules.size(); ++m) {
    for (std::size_t t = 0; t < plan.modules[m].tasks.size(); ++t) {
      const curriculum::Task& task = plan.modules[m].tasks[t];
      if (task.material.empty()) continue;
      const std::string path =
          "modules[" + std::to_string(m) + "].tasks[" + std::to_string(t) + "].material: ";
      const auto scene = live::find_scene(task.scene);
      if (!scene) {
        if (!db::MaterialsRepo(ctx.db()).find_by_name(task.material)) {
          throw ApiError(http::status::unprocessable_entity,
                         path + "no material named \"" + task.material + "\"");
        }
        continue;
      }
      scene_text_with_material(ctx.db(), scene->id, scene->text, task.material,
                               http::status::unprocessable_entity, path);
    }
  }
  return plan;
}

nlohmann::json curriculum_json(const db::CurriculumRecord& record) {
  return {{"id", record.id},
          {"name", record.name},
          {"definition", nlohmann::json::parse(record.definition_json)}};
}

}  // namespace

ApiResponse import_curriculum(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto plan = curriculum_of(ctx);
  db::Transaction tx(ctx.db());  // the change and its audit entry, both or neither
  const auto record =
      db::CurriculaRepo(ctx.db()).create(plan.name, curriculum::to_json(plan).dump(), ctx.now);
  audit_change(ctx.db(), admin.id, "curriculum.import", plan.name, ctx.now, nullptr,
               {{"id", record.id}, {"name", record.name}});
  tx.commit();
  return {http::status::created, curriculum_json(record)};
}

ApiResponse update_curriculum(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto plan = curriculum_of(ctx);
  auto& db = ctx.db();
  db::CurriculaRepo curricula(db);
  db::Transaction tx(db);  // "before", the change and its audit entry, no writer between
  const auto before = curricula.find(ctx.path_id);
  const auto after = curriculum::to_json(plan);
  curricula.update(ctx.path_id, plan.name, after.dump());
  // Only the changed places: a threshold edit reads "modules/0/tasks/1/thresholds/0/max".
  audit_change(db, admin.id, "curriculum.update", plan.name, ctx.now,
               before ? nlohmann::json::parse(before->definition_json, nullptr, false)
                      : nlohmann::json(nullptr),
               after);
  tx.commit();
  return {http::status::ok, curriculum_json(*curricula.find(ctx.path_id))};
}

ApiResponse export_curriculum(ApiContext& ctx) {
  ctx.require_role({db::Role::admin, db::Role::instructor});
  const auto record = db::CurriculaRepo(ctx.db()).find(ctx.path_id);
  if (!record) {
    throw ApiError(http::status::not_found,
                   "curriculum " + std::to_string(ctx.path_id) + " does not exist");
  }
  // The file an admin imports again: the definition itself, as a download.
  ApiResponse out{http::status::ok, nlohmann::json::parse(record->definition_json)};
  out.headers = {{"Content-Disposition",
                  "attachment; filename=\"curriculum-" + std::to_string(record->id) + ".json\""}};
  return out;
}

ApiResponse list_metrics(ApiContext& ctx) {
  ctx.user();
  auto out = nlohmann::json::array();
  for (const auto& m : curriculum::metric_catalogue()) {
    out.push_back({{"key", m.key},
                   {"name", m.name},
                   {"unit", m.unit},
                   {"display_unit", m.display_unit},
                   {"display_scale", m.display_scale},
                   {"decimals", m.decimals},
                   {"better", m.better},
                   {"definition", m.definition}});
  }
  return {http::status::ok, std::move(out)};
}

ApiResponse list_curricula(ApiContext& ctx) {
  ctx.user();
  return as_list(db::CurriculaRepo(ctx.db()).list());
}

}  // namespace incise::server::api
