#include "db/calibration_repo.h"

#include "db/statement.h"

namespace incise::db {
namespace {

constexpr const char* kJobColumns =
    "SELECT j.id, j.scene, j.method, j.per, j.budget, j.data_name, j.contacts, j.samples, "
    "j.status, j.cancel_requested, COALESCE(j.progress, ''), COALESCE(j.error, ''), "
    "COALESCE(j.node_id, ''), j.created_by, u.display_name, j.created_at, j.finished_at, "
    "COALESCE((SELECT m.name FROM materials m WHERE m.job_id = j.id ORDER BY m.id LIMIT 1), '') "
    "FROM calibration_jobs j JOIN users u ON u.id = j.created_by ";

CalibrationJob read_job(const Statement& q) {
  CalibrationJob j;
  j.id = q.int64(0);
  j.scene = q.text(1);
  j.method = q.text(2);
  j.per = q.text(3);
  j.budget = q.int64(4);
  j.data_name = q.text(5);
  j.contacts = q.int64(6);
  j.samples = q.int64(7);
  j.status = q.text(8);
  j.cancel_requested = q.int64(9) != 0;
  j.progress = q.text(10);
  j.error = q.text(11);
  j.node_id = q.text(12);
  j.created_by = q.int64(13);
  j.created_by_name = q.text(14);
  j.created_at = q.int64(15);
  j.finished_at = q.optional_int64(16);
  j.material = q.text(17);
  return j;
}

constexpr const char* kMaterialColumns =
    "SELECT m.id, m.name, m.scene, m.model, m.constants, m.job_id, m.method, m.misfit, "
    "m.created_by, u.display_name, m.created_at FROM materials m JOIN users u ON u.id = "
    "m.created_by ";

Material read_material(const Statement& q) {
  Material m;
  m.id = q.int64(0);
  m.name = q.text(1);
  m.scene = q.text(2);
  m.model = q.text(3);
  m.constants = q.text(4);
  m.job_id = q.optional_int64(5);
  m.method = q.text(6);
  m.misfit = q.real(7);
  m.created_by = q.int64(8);
  m.created_by_name = q.text(9);
  m.created_at = q.int64(10);
  return m;
}

}  // namespace

std::int64_t CalibrationJobsRepo::create(const NewCalibrationJob& job, std::int64_t now) {
  return db_
      .prepare(
          "INSERT INTO calibration_jobs (scene, method, per, budget, data_name, data, contacts, "
          "samples, status, node_id, created_by, created_at) VALUES (?, ?, ?, ?, ?, ?, ?, ?, "
          "'queued', ?, ?, ?) RETURNING id")
      .bind(1, job.scene)
      .bind(2, job.method)
      .bind(3, job.per)
      .bind(4, job.budget)
      .bind(5, job.data_name)
      .bind(6, job.data)
      .bind(7, job.contacts)
      .bind(8, job.samples)
      .bind(9, job.node_id)
      .bind(10, job.created_by)
      .bind(11, now)
      .insert();
}

std::optional<CalibrationJob> CalibrationJobsRepo::find(std::int64_t id) {
  auto q = db_.prepare(std::string(kJobColumns) + "WHERE j.id = ?");
  q.bind(1, id);
  if (!q.step()) return std::nullopt;
  return read_job(q);
}

std::vector<CalibrationJob> CalibrationJobsRepo::list(int limit) {
  auto q = db_.prepare(std::string(kJobColumns) + "ORDER BY j.id DESC LIMIT ?");
  q.bind(1, limit);
  std::vector<CalibrationJob> out;
  while (q.step())
    out.push_back(read_job(q));
  return out;
}

std::string CalibrationJobsRepo::data(std::int64_t id) {
  auto q = db_.prepare("SELECT data FROM calibration_jobs WHERE id = ?");
  q.bind(1, id);
  return q.step() ? q.text(0) : "";
}

std::string CalibrationJobsRepo::result(std::int64_t id) {
  auto q = db_.prepare("SELECT COALESCE(result, '') FROM calibration_jobs WHERE id = ?");
  q.bind(1, id);
  return q.step() ? q.text(0) : "";
}

std::optional<CalibrationJob> CalibrationJobsRepo::start_next(const std::string& node) {
  // A plain read, then a conditional write: no lock while nothing is queued, and a job cancelled
  // between the two is not started (its status is no longer 'queued').
  for (;;) {
    std::optional<std::int64_t> id;
    {
      auto q = db_.prepare(
          "SELECT id FROM calibration_jobs WHERE node_id = ? AND status = 'queued' ORDER BY id "
          "LIMIT 1");
      q.bind(1, node);
      if (q.step()) id = q.int64(0);
    }
    if (!id) return std::nullopt;
    auto started = db_.prepare(
        "UPDATE calibration_jobs SET status = 'running' WHERE id = ? AND status = 'queued' "
        "RETURNING id");
    started.bind(1, *id);
    if (started.step()) return find(*id);
  }
}

bool CalibrationJobsRepo::set_progress(std::int64_t id, const std::string& progress) {
  auto q = db_.prepare(
      "UPDATE calibration_jobs SET progress = ? WHERE id = ? RETURNING cancel_requested");
  q.bind(1, progress).bind(2, id);
  return q.step() && q.int64(0) != 0;
}

void CalibrationJobsRepo::finish(std::int64_t id, const std::string& status,
                                 const std::string& result, const std::string& error,
                                 std::int64_t now) {
  db_.prepare(
         "UPDATE calibration_jobs SET status = ?, result = ?, error = ?, finished_at = ? WHERE id "
         "= ?")
      .bind(1, status)
      .bind(2, result.empty() ? std::optional<std::string>() : std::optional(result))
      .bind(3, error.empty() ? std::optional<std::string>() : std::optional(error))
      .bind(4, now)
      .bind(5, id)
      .run();
}

bool CalibrationJobsRepo::request_cancel(std::int64_t id, std::int64_t now) {
  // Each a single conditional write, so that a job starting or ending meanwhile is never missed.
  auto queued = db_.prepare(
      "UPDATE calibration_jobs SET status = 'cancelled', cancel_requested = 1, error = "
      "'cancelled before it started', finished_at = ? WHERE id = ? AND status = 'queued' "
      "RETURNING id");
  queued.bind(1, now).bind(2, id);
  if (queued.step()) return true;
  auto running = db_.prepare(
      "UPDATE calibration_jobs SET cancel_requested = 1 WHERE id = ? AND status = 'running' "
      "RETURNING id");
  running.bind(1, id);
  return running.step();
}

int CalibrationJobsRepo::fail_unfinished(const std::string& node, const std::string& reason,
                                         std::int64_t now) {
  auto q = db_.prepare(
      "UPDATE calibration_jobs SET status = 'failed', error = ?, finished_at = ? WHERE node_id = "
      "? AND status IN ('queued', 'running') RETURNING id");
  q.bind(1, reason).bind(2, now).bind(3, node);
  int n = 0;
  while (q.step())
    ++n;
  return n;
}

std::int64_t MaterialsRepo::create(const Material& m, std::int64_t now) {
  return db_
      .prepare(
          "INSERT INTO materials (name, scene, model, constants, job_id, method, misfit, "
          "created_by, created_at) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?) RETURNING id")
      .bind(1, m.name)
      .bind(2, m.scene)
      .bind(3, m.model)
      .bind(4, m.constants)
      .bind(5, m.job_id)
      .bind(6, m.method)
      .bind(7, m.misfit)
      .bind(8, m.created_by)
      .bind(9, now)
      .insert();
}

std::optional<Material> MaterialsRepo::find(std::int64_t id) {
  auto q = db_.prepare(std::string(kMaterialColumns) + "WHERE m.id = ?");
  q.bind(1, id);
  if (!q.step()) return std::nullopt;
  return read_material(q);
}

std::optional<Material> MaterialsRepo::find_by_name(const std::string& name) {
  auto q = db_.prepare(std::string(kMaterialColumns) + "WHERE m.name = ?");
  q.bind(1, name);
  if (!q.step()) return std::nullopt;
  return read_material(q);
}

std::vector<Material> MaterialsRepo::list() {
  auto q = db_.prepare(std::string(kMaterialColumns) + "ORDER BY m.name");
  std::vector<Material> out;
  while (q.step())
    out.push_back(read_material(q));
  return out;
}

}  // namespace incise::db
