#pragma once
// Runs this node's tissue calibration jobs (db/calibration_repo.h, docs/calibration.md) one at a
// time on a thread of its own, so that a fit of minutes never holds an I/O thread or a request's
// connection. The thread starts with the first job and sleeps when none is queued; each job's
// progress goes to its row at most twice a second, and a cancel asked on any node is seen there.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "db/connection_pool.h"

namespace incise::server {

class CalibrationRunner {
 public:
  CalibrationRunner(db::ConnectionPool& pool, std::string node_id,
                    std::function<std::int64_t()> clock);
  // Stops the job running (cancelled: "the server stopped") and joins the thread.
  ~CalibrationRunner();
  CalibrationRunner(const CalibrationRunner&) = delete;
  CalibrationRunner& operator=(const CalibrationRunner&) = delete;

  // A job was queued on this node: run it (starts the thread the first time).
  void wake();
  void stop();

 private:
  void run();
  void run_job(std::int64_t job_id);

  db::ConnectionPool& pool_;
  std::string node_id_;
  std::function<std::int64_t()> clock_;
  std::mutex mutex_;
  std::condition_variable woken_;
  bool pending_ = false;
  bool stopping_ = false;
  std::atomic<bool> cancel_{false};  // the running job's
  std::thread thread_;
};

}  // namespace incise::server
