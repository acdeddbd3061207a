#include "db/connection_pool.h"

#include <chrono>
#include <stdexcept>
#include <string>

namespace incise::db {

ConnectionPool::ConnectionPool(DatabaseUrl url, std::size_t max_connections)
    : url_(std::move(url)), max_(max_connections) {
  if (max_ == 0) throw std::invalid_argument("a connection pool needs at least one connection");
}

ConnectionPool::~ConnectionPool() = default;

ConnectionPool::Lease ConnectionPool::acquire() {
  std::unique_lock lock(mutex_);
  // A connection held longer than this is a bug or an overload: fail the caller (its request
  // answers 500 and logs why) rather than stall its I/O thread for ever.
  if (!returned_.wait_for(lock, std::chrono::seconds(10),
                          [&] { return !idle_.empty() || open_ < max_; })) {
    throw DbError(0, "no database connection became free within 10 s (all " + std::to_string(max_) +
                         " in use)");
  }
  if (!idle_.empty()) {
    auto db = std::move(idle_.back());
    idle_.pop_back();
    return Lease(*this, std::move(db));
  }
  ++open_;  // reserved before opening, so that waiters count it
  lock.unlock();
  try {
    return Lease(*this, std::make_unique<Database>(url_));
  } catch (...) {
    lock.lock();
    --open_;
    returned_.notify_one();
    throw;
  }
}

std::size_t ConnectionPool::open_connections() const {
  std::lock_guard lock(mutex_);
  return open_;
}

void ConnectionPool::give_back(std::unique_ptr<Database> db) {
  // Never hand the next caller a transaction someone else left open (an exception between BEGIN
  // and the Transaction's destructor cannot do that, but a connection that fails to roll back
  // can), nor a connection the server closed: drop it, a new one is opened on demand.
  bool usable = true;
  try {
    if (db->in_transaction()) db->exec("ROLLBACK");
    usable = db->usable();
  } catch (...) {
    usable = false;
  }
  std::lock_guard lock(mutex_);
  if (usable) {
    idle_.push_back(std::move(db));
  } else {
    --open_;
  }
  returned_.notify_one();
}

ConnectionPool::Lease::Lease(ConnectionPool& pool, std::unique_ptr<Database> db)
    : pool_(&pool), db_(std::move(db)) {}

ConnectionPool::Lease::Lease(Lease&& other) noexcept
    : pool_(other.pool_), db_(std::move(other.db_)) {}

ConnectionPool::Lease::~Lease() {
  if (db_) pool_->give_back(std::move(db_));
}

}  // namespace incise::db
