#include "server/worker_pool.h"

#include <algorithm>
#include <boost/asio/post.hpp>
#include <iostream>
#include <thread>

namespace incise::server {

namespace {
std::size_t worker_count(std::size_t asked) {
  if (asked > 0) return asked;
  return std::max<std::size_t>(1, std::thread::hardware_concurrency() / 2);
}
}  // namespace

WorkerPool::WorkerPool(std::string name, std::size_t threads, std::size_t max_waiting)
    : name_(std::move(name)),
      threads_(worker_count(threads)),
      max_waiting_(max_waiting),
      pool_(threads_) {}

WorkerPool::~WorkerPool() {
  stop();
}

bool WorkerPool::try_post(std::function<void()> job) {
  if (waiting_.fetch_add(1) >= max_waiting_) {
    waiting_.fetch_sub(1);
    return false;
  }
  boost::asio::post(pool_, [this, job = std::move(job)] {
    waiting_.fetch_sub(1);
    try {
      job();
    } catch (const std::exception& e) {
      // A job answers its own errors; this only keeps a worker alive if that answer failed.
      std::cerr << "incise-server: " << name_ << ": " << e.what() << "\n";
    } catch (...) {
      std::cerr << "incise-server: " << name_ << ": unknown error\n";
    }
  });
  return true;
}

void WorkerPool::stop() {
  pool_.stop();
  pool_.join();
}

}  // namespace incise::server
