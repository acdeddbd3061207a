#include "db/statement.h"

#include "db/connection.h"
#include "db/db_error.h"

namespace incise::db {

Statement::Statement(std::unique_ptr<detail::Cursor> cursor) : cursor_(std::move(cursor)) {}

Statement::~Statement() = default;

Statement::Statement(Statement&& other) noexcept = default;

Statement& Statement::bind(int index, std::int64_t value) {
  cursor_->bind_int64(index, value);
  return *this;
}

Statement& Statement::bind(int index, double value) {
  cursor_->bind_double(index, value);
  return *this;
}

Statement& Statement::bind(int index, std::string_view text) {
  cursor_->bind_text(index, text);
  return *this;
}

Statement& Statement::bind_blob(int index, std::span<const std::uint8_t> bytes) {
  cursor_->bind_blob(index, bytes);
  return *this;
}

Statement& Statement::bind_null(int index) {
  cursor_->bind_null(index);
  return *this;
}

bool Statement::step() {
  return cursor_->step();
}

void Statement::run() {
  while (step()) {
  }
}

std::int64_t Statement::insert() {
  if (!step()) throw DbError(0, "insert: the statement returned no id (no RETURNING id?)");
  const std::int64_t id = int64(0);
  run();
  return id;
}

void Statement::reset() {
  cursor_->reset();
}

int Statement::columns() const {
  return cursor_->columns();
}

bool Statement::is_null(int column) const {
  return cursor_->is_null(column);
}

std::int64_t Statement::int64(int column) const {
  return cursor_->int64(column);
}

double Statement::real(int column) const {
  return cursor_->real(column);
}

std::string Statement::text(int column) const {
  return cursor_->text(column);
}

std::vector<std::uint8_t> Statement::blob(int column) const {
  return cursor_->blob(column);
}

std::optional<std::int64_t> Statement::optional_int64(int column) const {
  if (is_null(column)) return std::nullopt;
  return int64(column);
}

}  // namespace incise::db
