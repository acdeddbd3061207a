#pragma once
// Storage throws typed errors (STYLE.md: "two error styles, kept apart"); callers map them to
// HTTP statuses. Destructors in db/ never throw.
#include <stdexcept>
#include <string>
#include <utility>

namespace incise::db {

// Any database failure. `code()` is SQLite's extended result code (0 on PostgreSQL);
// `sqlstate()` is PostgreSQL's five-character SQLSTATE (empty on SQLite).
class DbError : public std::runtime_error {
 public:
  DbError(int code, const std::string& message, std::string sqlstate = {})
      : std::runtime_error(message), code_(code), sqlstate_(std::move(sqlstate)) {}
  int code() const { return code_; }
  const std::string& sqlstate() const { return sqlstate_; }

 private:
  int code_;
  std::string sqlstate_;
};

// A UNIQUE, CHECK or FOREIGN KEY constraint refused a write; nothing was changed.
class ConstraintError : public DbError {
 public:
  using DbError::DbError;
};

// The row the caller asked for does not exist.
class NotFound : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The operation conflicts with stored data (e.g. an overlapping booking); nothing was changed.
class Conflict : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace incise::db
