#pragma once
// Connections for many threads: a request, an agent's station lookup or a replay's load leases
// one for as long as it works and gives it back. At most `max_connections` are open at once; a
// caller waits while all are leased (PostgreSQL: the server's connection budget; SQLite: one per
// I/O thread is plenty, WAL lets readers and one writer work side by side). A connection that is
// returned inside a transaction (an exception left it open) is rolled back first, and one that
// failed in a way that broke it (the server went away) is closed and replaced on the next lease.
#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

#include "db/database.h"
#include "db/database_url.h"

namespace incise::db {

class ConnectionPool {
 public:
  ConnectionPool(DatabaseUrl url, std::size_t max_connections);
  ~ConnectionPool();
  ConnectionPool(const ConnectionPool&) = delete;
  ConnectionPool& operator=(const ConnectionPool&) = delete;

  class Lease {
   public:
    Lease(Lease&& other) noexcept;
    Lease& operator=(Lease&&) = delete;
    Lease(const Lease&) = delete;
    ~Lease();
    Database& operator*() const { return *db_; }
    Database* operator->() const { return db_.get(); }

   private:
    friend class ConnectionPool;
    Lease(ConnectionPool& pool, std::unique_ptr<Database> db);
    ConnectionPool* pool_;
    std::unique_ptr<Database> db_;
  };

  // A connection, opened if none is idle and fewer than max are open; waits otherwise. Throws
  // DbError when a new connection cannot be opened.
  Lease acquire();
  const DatabaseUrl& url() const { return url_; }
  std::size_t max_connections() const { return max_; }
  std::size_t open_connections() const;

 private:
  void give_back(std::unique_ptr<Database> db);

  const DatabaseUrl url_;
  const std::size_t max_;
  mutable std::mutex mutex_;
  std::condition_variable returned_;
  std::vector<std::unique_ptr<Database>> idle_;
  std::size_t open_ = 0;
};

}  // namespace incise::db
