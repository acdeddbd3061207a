#pragma once
// Threads for the requests that take long, off the I/O threads, so that a burst of them never
// delays other requests or the live streams. A bounded number of threads bounds their memory,
// and a bounded queue turns a flood into quick 503s instead of minutes of waiting. The server has
// two (AppState):
// - the password workers: logins, password changes, new users and resets (http_session.h:
//   checks_password), argon2id's 50 ms of CPU and 64 MiB each;
// - the long reads: a session's review, the scores' CSV export and a replay's recording
//   (http_session.h: is_long_read), which read a whole recording or table.
#include <atomic>
#include <boost/asio/thread_pool.hpp>
#include <cstddef>
#include <functional>
#include <string>

namespace incise::server {

class WorkerPool {
 public:
  // threads 0: half the machine's cores, at least one. `name` goes in its log lines.
  explicit WorkerPool(std::string name, std::size_t threads = 0, std::size_t max_waiting = 64);
  ~WorkerPool();

  // Runs `job` on a worker; false (and `job` is dropped) when max_waiting jobs are queued already.
  bool try_post(std::function<void()> job);
  // Finishes the running jobs, drops the queued ones and joins the threads (shutdown).
  void stop();

  std::size_t threads() const { return threads_; }

 private:
  std::string name_;
  std::size_t threads_;
  std::size_t max_waiting_;
  std::atomic<std::size_t> waiting_{0};
  boost::asio::thread_pool pool_;
};

}  // namespace incise::server
