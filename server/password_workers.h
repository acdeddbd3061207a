#pragma once
// The threads that check and hash passwords (argon2id: about 50 ms of CPU and 64 MiB each).
// Logins, password changes, new users and resets (http_session.h: checks_password) run here
// rather than on the I/O threads, so that a burst of them never delays other requests or the
// live streams; a bounded number of threads bounds their memory, and a bounded queue turns a
// flood into quick 503s instead of minutes of waiting.
#include <atomic>
#include <boost/asio/thread_pool.hpp>
#include <cstddef>
#include <functional>

namespace incise::server {

class PasswordWorkers {
 public:
  // threads 0: half the machine's cores, at least one.
  explicit PasswordWorkers(std::size_t threads = 0, std::size_t max_waiting = 64);
  ~PasswordWorkers();

  // Runs `job` on a worker; false (and `job` is dropped) when max_waiting jobs are queued already.
  bool try_post(std::function<void()> job);
  // Finishes the running jobs, drops the queued ones and joins the threads (shutdown).
  void stop();

  std::size_t threads() const { return threads_; }

 private:
  std::size_t threads_;
  std::size_t max_waiting_;
  std::atomic<std::size_t> waiting_{0};
  boost::asio::thread_pool pool_;
};

}  // namespace incise::server
