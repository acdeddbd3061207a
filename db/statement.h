#pragma once
// A prepared statement. Bind parameters by 1-based index, step through rows, read columns by
// 0-based index. Finalised on destruction.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace incise::db {

namespace detail {
class Cursor;
}

class Statement {
 public:
  explicit Statement(std::unique_ptr<detail::Cursor> cursor);
  ~Statement();
  Statement(Statement&& other) noexcept;
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  Statement& operator=(Statement&&) = delete;

  Statement& bind(int index, std::int64_t value);
  Statement& bind(int index, int value) { return bind(index, std::int64_t{value}); }
  Statement& bind(int index, double value);
  Statement& bind(int index, std::string_view text);
  Statement& bind(int index, const char* text) { return bind(index, std::string_view(text)); }
  Statement& bind_blob(int index, std::span<const std::uint8_t> bytes);
  Statement& bind_null(int index);
  template <class T>
  Statement& bind(int index, const std::optional<T>& value) {
    return value ? bind(index, *value) : bind_null(index);
  }

  // Advances to the next row; false when done. Throws DbError/ConstraintError on failure.
  bool step();
  // Runs a statement that returns no rows.
  void run();
  // Runs an INSERT ... RETURNING id and returns the new row's id (both engines; SQLite's rowid and
  // last_insert_id would not tell one PostgreSQL connection's insert from another's).
  std::int64_t insert();
  void reset();

  int columns() const;  // of the current row
  bool is_null(int column) const;
  std::int64_t int64(int column) const;
  double real(int column) const;
  std::string text(int column) const;
  std::vector<std::uint8_t> blob(int column) const;
  std::optional<std::int64_t> optional_int64(int column) const;

 private:
  std::unique_ptr<detail::Cursor> cursor_;
};

}  // namespace incise::db
