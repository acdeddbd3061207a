#pragma once
// Tissue calibration's jobs and the named materials saved from them (migration 014,
// docs/calibration.md). A job is queued by the node that accepted it, which alone runs it
// (node_id); progress, result and error are JSON or text the job writes as it goes. A cancel is a
// flag in the row, so that any node can ask and the running node sees it at its next progress.
// Materials are never changed once saved: a recording names the material its session ran with,
// and its replay must find the same constants.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/database.h"

namespace incise::db {

struct CalibrationJob {
  std::int64_t id = 0;
  std::string scene;   // scene id, e.g. "scenes/calibration/cube.json"
  std::string method;  // "ga", "cmaes", "lm"
  std::string per;     // "label", "node"
  std::int64_t budget = 0;
  std::string data_name;
  std::int64_t contacts = 0;
  std::int64_t samples = 0;
  std::string status;  // "queued", "running", "done", "failed", "cancelled"
  bool cancel_requested = false;
  std::string progress;  // JSON or ""
  std::string error;     // "" unless failed
  std::string node_id;
  std::int64_t created_by = 0;
  std::string created_by_name;
  std::int64_t created_at = 0;
  std::optional<std::int64_t> finished_at;
  std::string material;  // the name of the material saved from it, or ""
};

struct NewCalibrationJob {
  std::string scene, method, per;
  std::int64_t budget = 0;
  std::string data_name, data;
  std::int64_t contacts = 0, samples = 0;
  std::string node_id;
  std::int64_t created_by = 0;
};

class CalibrationJobsRepo {
 public:
  explicit CalibrationJobsRepo(Database& db) : db_(db) {}

  // Queues a job; returns its id.
  std::int64_t create(const NewCalibrationJob& job, std::int64_t now);
  std::optional<CalibrationJob> find(std::int64_t id);
  // Newest first, at most `limit`.
  std::vector<CalibrationJob> list(int limit = 100);
  // The job's data file and result JSON ("" until done).
  std::string data(std::int64_t id);
  std::string result(std::int64_t id);

  // The oldest queued job of `node`, now running; nullopt when none is queued.
  std::optional<CalibrationJob> start_next(const std::string& node);
  // Progress JSON of a running job; returns whether a cancel was asked for meanwhile.
  bool set_progress(std::int64_t id, const std::string& progress);
  // Ends a running job: "done" with its result, or "failed" / "cancelled" with a reason.
  void finish(std::int64_t id, const std::string& status, const std::string& result,
              const std::string& error, std::int64_t now);
  // Asks a queued or running job to stop: a queued one is cancelled at once. False when it has
  // ended already.
  bool request_cancel(std::int64_t id, std::int64_t now);
  // At start-up: the jobs `node` left queued or running end as failed with `reason`.
  int fail_unfinished(const std::string& node, const std::string& reason, std::int64_t now);

 private:
  Database& db_;
};

struct Material {
  std::int64_t id = 0;
  std::string name;
  std::string scene;
  std::string model;
  std::string constants;  // JSON {"material": {...}, "materials"?: {...}}
  std::optional<std::int64_t> job_id;
  std::string method;
  double misfit = 0;
  std::int64_t created_by = 0;
  std::string created_by_name;
  std::int64_t created_at = 0;
};

class MaterialsRepo {
 public:
  explicit MaterialsRepo(Database& db) : db_(db) {}

  // Throws ConstraintError when the name is taken.
  std::int64_t create(const Material& material, std::int64_t now);
  std::optional<Material> find(std::int64_t id);
  std::optional<Material> find_by_name(const std::string& name);
  std::vector<Material> list();

 private:
  Database& db_;
};

}  // namespace incise::db
