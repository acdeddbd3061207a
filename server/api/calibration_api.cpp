// Tissue calibration (docs/calibration.md, docs/api.md "Tissue calibration"): the scenes it can
// fit, jobs that fit them to an uploaded probe data file in the background
// (server/calibration_runner.h), and the named materials saved from finished jobs.
#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "curriculum/curriculum_json.h"
#include "db/calibration_repo.h"
#include "db/curricula_repo.h"
#include "db/db_error.h"
#include "db/transaction.h"
#include "server/api/api_error.h"
#include "server/api/audit_change.h"
#include "server/api/handlers.h"
#include "server/api/request_fields.h"
#include "server/calibration_runner.h"
#include "server/calibration_scenes.h"
#include "server/live/scene_library.h"
#include "server/time_text.h"
#include "server/wire_text.h"
#include "sim/calibrate/optimisers.h"

namespace incise::server::api {
namespace {

using nlohmann::json;

constexpr std::int64_t kDefaultBudget = 2000;
constexpr std::int64_t kMaxBudget = 20000;

json job_json(const db::CalibrationJob& j) {
  json progress = nullptr;
  if (!j.progress.empty()) progress = json::parse(j.progress, nullptr, false);
  if (progress.is_discarded()) progress = nullptr;
  return {{"id", j.id},
          {"scene", j.scene},
          {"method", j.method},
          {"per", j.per},
          {"budget", j.budget},
          {"data_name", j.data_name},
          {"contacts", j.contacts},
          {"samples", j.samples},
          {"status", j.status},
          {"progress", progress},
          {"created_at", format_utc(j.created_at)},
          {"created_by", j.created_by_name},
          {"finished_at", j.finished_at ? json(format_utc(*j.finished_at)) : json(nullptr)},
          {"error", j.error.empty() ? json(nullptr) : json(j.error)},
          {"material", j.material.empty() ? json(nullptr) : json(j.material)}};
}

// The keys of the stored curricula's tasks that name each material.
std::map<std::string, std::vector<std::string>> tasks_by_material(db::Database& db) {
  std::map<std::string, std::vector<std::string>> out;
  for (const auto& record : db::CurriculaRepo(db).list()) {
    try {
      const auto plan = curriculum::parse_curriculum(json::parse(record.definition_json));
      for (const auto& module : plan.modules) {
        for (const auto& task : module.tasks) {
          if (!task.material.empty()) out[task.material].push_back(task.key);
        }
      }
    } catch (const std::exception&) {
      // A stored curriculum was valid when saved; one that no longer parses names nothing here.
    }
  }
  return out;
}

json material_json(const db::Material& m, const std::vector<std::string>& tasks) {
  const json constants = json::parse(m.constants, nullptr, false);
  const json material =
      constants.is_object() ? constants.value("material", json::object()) : json::object();
  json out = {{"id", m.id},
              {"name", m.name},
              {"scene", m.scene},
              {"model", m.model},
              {"E", material.value("E", 0.0)},
              {"nu", material.value("nu", 0.0)},
              {"density", material.value("density", 0.0)},
              {"damping", material.value("damping", 0.0)},
              {"method", m.method},
              {"misfit", m.misfit},
              {"job", m.job_id ? json(*m.job_id) : json(nullptr)},
              {"created_at", format_utc(m.created_at)},
              {"created_by", m.created_by_name},
              {"tasks", tasks}};
  if (constants.is_object() && constants.contains("materials")) {
    out["materials"] = constants["materials"];
  }
  return out;
}

db::CalibrationJob existing_job(db::Database& db, std::int64_t id) {
  auto job = db::CalibrationJobsRepo(db).find(id);
  if (!job) {
    throw ApiError(http::status::not_found,
                   "calibration job " + std::to_string(id) + " does not exist");
  }
  return *job;
}

}  // namespace

ApiResponse list_calibration_scenes(ApiContext& ctx) {
  ctx.require_role({db::Role::admin});
  json scenes = json::array();
  for (const CalibrationScene& s : calibration_scenes()) {
    json per = json::array({"label"});
    if (s.per_node) per.push_back("node");
    scenes.push_back({{"id", s.id},
                      {"title", s.title},
                      {"model", s.model},
                      {"per", per},
                      {"has_example", s.has_example}});
  }
  return {http::status::ok, {{"scenes", scenes}}};
}

ApiResponse calibration_example(ApiContext& ctx) {
  ctx.require_role({db::Role::admin});
  const std::string_view target(ctx.request.target().data(), ctx.request.target().size());
  const auto question = target.find('?');
  const auto value = question == std::string_view::npos
                         ? std::nullopt
                         : query_value(target.substr(question + 1), "scene");
  const auto decoded = value ? percent_decoded(*value) : std::optional<std::string>("");
  if (!decoded) throw ApiError(http::status::bad_request, "scene: malformed percent-encoding");
  const std::string& scene = *decoded;
  const auto example = live::find_example_data(scene);
  if (!example) {
    throw ApiError(http::status::not_found, "no example data for scene \"" + scene + "\"");
  }
  ApiResponse out{http::status::ok, nullptr};
  out.text_body = std::string(*example);
  out.content_type = "text/csv; charset=utf-8";
  std::string name = scene.substr(scene.rfind('/') + 1);
  name = name.substr(0, name.rfind('.')) + "_pushes.csv";
  out.headers = {{"Content-Disposition", "attachment; filename=\"" + name + "\""}};
  return out;
}

ApiResponse create_calibration_job(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"scene", "method", "per", "budget", "data", "data_name"});
  db::NewCalibrationJob job;
  job.scene = fields.string("scene");
  job.method = fields.string("method");
  if (!sim::calibrate::method_named(job.method)) {
    throw ApiError(http::status::unprocessable_entity,
                   "method must be \"ga\", \"cmaes\" or \"lm\"");
  }
  job.per = fields.string_or("per", "label");
  if (job.per != "label" && job.per != "node") {
    throw ApiError(http::status::unprocessable_entity, "per must be \"label\" or \"node\"");
  }
  job.budget = fields.has("budget") ? fields.integer("budget") : kDefaultBudget;
  if (job.budget < 1 || job.budget > kMaxBudget) {
    throw ApiError(http::status::unprocessable_entity,
                   "budget must be a whole number from 1 to " + std::to_string(kMaxBudget));
  }
  job.data_name = fields.text_or("data_name", "data.csv");
  if (job.data_name.empty() || job.data_name.size() > 120) {
    throw ApiError(http::status::unprocessable_entity, "data_name must be 1-120 characters");
  }
  job.data = fields.string("data");
  const auto& scenes = calibration_scenes();
  const auto scene = std::find_if(scenes.begin(), scenes.end(),
                                  [&](const CalibrationScene& s) { return s.id == job.scene; });
  if (scene == scenes.end()) {
    throw ApiError(http::status::unprocessable_entity,
                   "scene: \"" + job.scene + "\" is not a scene this server can calibrate");
  }
  if (job.per == "node" && !scene->per_node) {
    throw ApiError(
        http::status::unprocessable_entity,
        "per: per-node moduli are the mass-spring model's, and this scene uses " + scene->model);
  }
  try {
    const CalibrationSetup setup = calibration_setup(job.scene, job.data);
    check_job_size(setup, job.per == "node", job.method);
    job.contacts = static_cast<std::int64_t>(setup.data.contacts.size());
    for (const auto& c : setup.data.contacts)
      job.samples += static_cast<std::int64_t>(c.samples.size());
  } catch (const sim::calibrate::CalibrationError& e) {
    throw ApiError(http::status::unprocessable_entity, e.what());
  }
  job.node_id = ctx.app.config().node_id;
  job.created_by = admin.id;
  db::Transaction tx(ctx.db());
  db::CalibrationJobsRepo jobs(ctx.db());
  const auto id = jobs.create(job, ctx.now);
  audit_change(ctx.db(), admin.id, "calibration.start",
               "job " + std::to_string(id) + " " + job.scene, ctx.now, nullptr,
               {{"scene", job.scene},
                {"method", job.method},
                {"per", job.per},
                {"budget", job.budget},
                {"data_name", job.data_name}});
  tx.commit();
  ctx.app.calibration_runner().wake();
  return {http::status::created, {{"job", job_json(*jobs.find(id))}}};
}

ApiResponse list_calibration_jobs(ApiContext& ctx) {
  ctx.require_role({db::Role::admin});
  json jobs = json::array();
  for (const auto& j : db::CalibrationJobsRepo(ctx.db()).list())
    jobs.push_back(job_json(j));
  return {http::status::ok, {{"jobs", jobs}}};
}

ApiResponse get_calibration_job(ApiContext& ctx) {
  ctx.require_role({db::Role::admin});
  const auto job = existing_job(ctx.db(), ctx.path_id);
  json result = nullptr;
  if (job.status == "done" || job.status == "cancelled") {
    const std::string text = db::CalibrationJobsRepo(ctx.db()).result(job.id);
    if (!text.empty()) result = json::parse(text, nullptr, false);
    if (result.is_discarded()) result = nullptr;
  }
  return {http::status::ok, {{"job", job_json(job)}, {"result", result}}};
}

ApiResponse cancel_calibration_job(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  db::CalibrationJobsRepo jobs(ctx.db());
  const auto job = existing_job(ctx.db(), ctx.path_id);
  if (!jobs.request_cancel(job.id, ctx.now)) {
    // Read again: it may have ended between the two.
    throw ApiError(http::status::conflict, "calibration job " + std::to_string(job.id) +
                                               " has ended (" +
                                               existing_job(ctx.db(), job.id).status + ")");
  }
  audit_change(ctx.db(), admin.id, "calibration.cancel", "job " + std::to_string(job.id), ctx.now,
               nullptr, nullptr);
  return {http::status::ok, {{"job", job_json(existing_job(ctx.db(), job.id))}}};
}

ApiResponse create_material(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"job", "name"});
  const auto job_id = fields.integer("job");
  const auto name = fields.text("name");
  if (name.empty() || name.size() > 80) {
    throw ApiError(http::status::unprocessable_entity, "name must be 1-80 characters");
  }
  auto& db = ctx.db();
  db::Transaction tx(db);
  const auto job = existing_job(db, job_id);
  if (job.status != "done") {
    throw ApiError(http::status::conflict, "calibration job " + std::to_string(job.id) + " is " +
                                               job.status + ": only a finished fit is saved");
  }
  const json result = json::parse(db::CalibrationJobsRepo(db).result(job.id), nullptr, false);
  if (!result.is_object() || !result.contains("material")) {
    throw ApiError(http::status::conflict,
                   "calibration job " + std::to_string(job.id) + " has no result to save");
  }
  db::MaterialsRepo materials(db);
  if (materials.find_by_name(name)) {
    throw ApiError(http::status::conflict, "a material named \"" + name + "\" exists");
  }
  json constants = {{"material", result["material"]}};
  if (result.contains("materials")) constants["materials"] = result["materials"];
  db::Material m;
  m.name = name;
  m.scene = job.scene;
  m.model = result["material"].value("model", "mss");
  m.constants = constants.dump();
  m.job_id = job.id;
  m.method = job.method;
  m.misfit = result.value("calibration", json::object()).value("misfit", 0.0);
  m.created_by = admin.id;
  const auto id = materials.create(m, ctx.now);
  const auto saved = *materials.find(id);
  audit_change(db, admin.id, "material.create", name, ctx.now, nullptr, material_json(saved, {}));
  tx.commit();
  return {http::status::created, {{"material", material_json(saved, {})}}};
}

ApiResponse list_materials(ApiContext& ctx) {
  ctx.require_role({db::Role::admin, db::Role::instructor});
  const auto used = tasks_by_material(ctx.db());
  json out = json::array();
  for (const auto& m : db::MaterialsRepo(ctx.db()).list()) {
    const auto found = used.find(m.name);
    out.push_back(
        material_json(m, found != used.end() ? found->second : std::vector<std::string>{}));
  }
  return {http::status::ok, {{"materials", out}}};
}

}  // namespace incise::server::api
