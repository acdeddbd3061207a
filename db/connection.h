#pragma once
// The engine seam under Database and Statement (internal to db/). One Connection per open
// database, one Cursor per prepared statement; SQLite and PostgreSQL each implement both. The
// repositories never see this: they speak the SQL both engines share, through Database.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "db/database_url.h"

namespace incise::db::detail {

class Cursor {
 public:
  virtual ~Cursor() = default;
  // Parameters are 1-based, columns 0-based (as in Statement).
  virtual void bind_int64(int index, std::int64_t value) = 0;
  virtual void bind_double(int index, double value) = 0;
  virtual void bind_text(int index, std::string_view text) = 0;
  virtual void bind_blob(int index, std::span<const std::uint8_t> bytes) = 0;
  virtual void bind_null(int index) = 0;
  virtual bool step() = 0;
  virtual void reset() = 0;         // forgets the result and the bindings
  virtual int columns() const = 0;  // of the current result
  virtual bool is_null(int column) const = 0;
  virtual std::int64_t int64(int column) const = 0;
  virtual double real(int column) const = 0;
  virtual std::string text(int column) const = 0;
  virtual std::vector<std::uint8_t> blob(int column) const = 0;
};

class Connection {
 public:
  virtual ~Connection() = default;
  virtual Dialect dialect() const = 0;
  virtual void exec(std::string_view sql) = 0;
  virtual std::unique_ptr<Cursor> prepare(std::string_view sql) = 0;
  virtual int changes() const = 0;
  virtual bool in_transaction() const = 0;
  virtual bool usable() const = 0;          // false once the connection broke (server gone)
  virtual void* native_handle() const = 0;  // sqlite3* or PGconn*
};

std::unique_ptr<Connection> open_sqlite(const std::filesystem::path& path);
std::unique_ptr<Connection> open_postgresql(const std::string& uri);

}  // namespace incise::db::detail
