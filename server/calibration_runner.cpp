#include "server/calibration_runner.h"

#include <chrono>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "db/calibration_repo.h"
#include "server/calibration_scenes.h"
#include "sim/calibrate/calibration_json.h"

namespace incise::server {

CalibrationRunner::CalibrationRunner(db::ConnectionPool& pool, std::string node_id,
                                     std::function<std::int64_t()> clock)
    : pool_(pool), node_id_(std::move(node_id)), clock_(std::move(clock)) {}

CalibrationRunner::~CalibrationRunner() {
  stop();
}

void CalibrationRunner::wake() {
  std::lock_guard lock(mutex_);
  if (stopping_) return;
  pending_ = true;
  if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
  woken_.notify_one();
}

void CalibrationRunner::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    cancel_ = true;
    woken_.notify_one();
  }
  if (thread_.joinable()) thread_.join();
}

void CalibrationRunner::run() {
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      // wake() follows every job this node queues; the drain below takes any that came meanwhile.
      woken_.wait(lock, [this] { return pending_ || stopping_; });
      if (stopping_) return;
      pending_ = false;
    }
    try {
      for (;;) {
        std::optional<db::CalibrationJob> job;
        {
          auto db = pool_.acquire();
          job = db::CalibrationJobsRepo(*db).start_next(node_id_);
        }
        if (!job) break;
        cancel_ = false;
        {
          std::lock_guard lock(mutex_);
          if (stopping_) cancel_ = true;
        }
        run_job(job->id);
        std::lock_guard lock(mutex_);
        if (stopping_) return;
      }
    } catch (const std::exception& e) {
      std::cerr << "incise-server: calibration runner: " << e.what() << "\n";
    }
  }
}

void CalibrationRunner::run_job(std::int64_t job_id) {
  using namespace sim::calibrate;
  std::string status = "done";
  std::string result;
  std::string error;
  try {
    std::optional<db::CalibrationJob> job;
    std::string data;
    {
      auto db = pool_.acquire();
      db::CalibrationJobsRepo jobs(*db);
      job = jobs.find(job_id);
      data = jobs.data(job_id);
    }
    if (!job) return;
    const CalibrationSetup setup = calibration_setup(job->scene, data);
    CalibrationOptions options;
    options.method = *method_named(job->method);
    options.parameters =
        job->per == "node" ? ParameterKind::node_moduli : ParameterKind::label_materials;
    options.max_evaluations = static_cast<int>(job->budget);
    options.cancel = &cancel_;
    auto last_write = std::chrono::steady_clock::now() - std::chrono::seconds(1);
    options.progress = [&](const Progress& progress) {
      const auto now = std::chrono::steady_clock::now();
      if (now - last_write < std::chrono::milliseconds(500)) return;
      if (!std::isfinite(progress.misfit)) return;  // nothing evaluable yet: nothing to show
      last_write = now;
      const nlohmann::json line = {{"iteration", progress.iteration},
                                   {"evaluations", progress.evaluations},
                                   {"misfit", progress.misfit}};
      try {
        auto db = pool_.acquire();
        if (db::CalibrationJobsRepo(*db).set_progress(job_id, line.dump())) cancel_ = true;
      } catch (const std::exception& e) {
        std::cerr << "incise-server: calibration job " << job_id << ": progress: " << e.what()
                  << "\n";
      }
    };
    const CalibrationResult fit = calibrate(setup.scene, setup.mesh, setup.data, options);
    nlohmann::json json = calibration_json(fit, options.method);
    json["calibration"]["scene"] = job->scene;
    json["calibration"]["data"] = job->data_name;
    result = json.dump();
    if (fit.search.stopped == "cancelled") {
      status = "cancelled";
      std::lock_guard lock(mutex_);
      error = stopping_ ? "the server stopped while it ran" : "cancelled";
    }
    // The last progress, whatever the throttle held back (a misfit that never became finite is
    // JSON null: the job then fails below or shows no fit).
    const nlohmann::json line = {{"iteration", fit.search.iterations},
                                 {"evaluations", fit.search.evaluations},
                                 {"misfit", fit.search.misfit}};
    auto db = pool_.acquire();
    db::CalibrationJobsRepo(*db).set_progress(job_id, line.dump());
  } catch (const std::exception& e) {
    status = "failed";
    result.clear();
    error = e.what();
  }
  try {
    auto db = pool_.acquire();
    db::CalibrationJobsRepo(*db).finish(job_id, status, result, error, clock_());
  } catch (const std::exception& e) {
    std::cerr << "incise-server: calibration job " << job_id << ": " << e.what() << "\n";
  }
}

}  // namespace incise::server
