// The PostgreSQL engine behind Database (libpq). Statements keep the SQL the repositories write
// for SQLite: '?' and '?N' placeholders are rewritten to '$N' once, at prepare. Parameters go as
// text (exact: integers in decimal, doubles in their shortest round-trip form) except blobs, which
// go binary; results come back as text and are read the way SQLite's column accessors read theirs.
#include <libpq-fe.h>

#include <charconv>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string_view>
#include <system_error>

#include "db/connection.h"
#include "db/database.h"

namespace incise::db::detail {
namespace {

// Type OIDs from PostgreSQL's catalog (pg_type.dat), stable across versions.
constexpr Oid kBoolOid = 16;
constexpr Oid kByteaOid = 17;
constexpr Oid kInt8Oid = 20;
constexpr Oid kFloat8Oid = 701;

std::string trimmed(const char* message) {
  std::string text = message ? message : "";
  while (!text.empty() && (text.back() == '\n' || text.back() == ' '))
    text.pop_back();
  return text;
}

// Throws the typed error for a failed result: class 23 (integrity constraint violation) is a
// ConstraintError, as SQLite's constraint codes are.
[[noreturn]] void throw_result_error(PGconn* conn, const PGresult* result,
                                     std::string_view context) {
  const char* state = result ? PQresultErrorField(result, PG_DIAG_SQLSTATE) : nullptr;
  std::string sqlstate = state ? state : "";
  std::string message = std::string(context) + ": " +
                        trimmed(result ? PQresultErrorMessage(result) : PQerrorMessage(conn));
  if (sqlstate.starts_with("23")) throw ConstraintError(0, message, std::move(sqlstate));
  throw DbError(0, message, std::move(sqlstate));
}

struct ResultDeleter {
  void operator()(PGresult* r) const { PQclear(r); }
};
using Result = std::unique_ptr<PGresult, ResultDeleter>;

// '?N' -> '$N'; a bare '?' takes one more than the largest number so far (SQLite's rule). Quoted
// strings, quoted identifiers and comments pass through untouched. Returns the parameter count.
int rewrite_placeholders(std::string_view sql, std::string& out) {
  out.clear();
  out.reserve(sql.size() + 8);
  int largest = 0;
  for (std::size_t i = 0; i < sql.size();) {
    const char c = sql[i];
    if (c == '\'' || c == '"') {
      const std::size_t end = sql.find(c, i + 1);
      const std::size_t stop = end == std::string_view::npos ? sql.size() : end + 1;
      out.append(sql.substr(i, stop - i));
      i = stop;
    } else if (c == '-' && i + 1 < sql.size() && sql[i + 1] == '-') {
      const std::size_t end = sql.find('\n', i);
      const std::size_t stop = end == std::string_view::npos ? sql.size() : end;
      out.append(sql.substr(i, stop - i));
      i = stop;
    } else if (c == '/' && i + 1 < sql.size() && sql[i + 1] == '*') {
      const std::size_t end = sql.find("*/", i + 2);
      const std::size_t stop = end == std::string_view::npos ? sql.size() : end + 2;
      out.append(sql.substr(i, stop - i));
      i = stop;
    } else if (c == '?') {
      std::size_t j = i + 1;
      int number = 0;
      while (j < sql.size() && sql[j] >= '0' && sql[j] <= '9' && number < 100000)
        number = number * 10 + (sql[j++] - '0');
      if (j == i + 1) number = largest + 1;
      largest = std::max(largest, number);
      out += '$';
      out += std::to_string(number);
      i = j;
    } else {
      out += c;
      ++i;
    }
  }
  return largest;
}

class PgConnection;

class PgCursor final : public Cursor {
 public:
  PgCursor(PgConnection& owner, PGconn* conn, std::string_view sql) : owner_(owner), conn_(conn) {
    params_.resize(static_cast<std::size_t>(rewrite_placeholders(sql, sql_)));
  }

  void bind_int64(int index, std::int64_t value) override {
    char text[24];
    const auto end = std::to_chars(text, text + sizeof text, value).ptr;
    set(index, kInt8Oid, std::string(text, end), 0);
  }
  void bind_double(int index, double value) override {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, value).ptr;  // shortest exact form
    set(index, kFloat8Oid, std::string(text, end), 0);
  }
  void bind_text(int index, std::string_view text) override {
    if (text.find('\0') != std::string_view::npos) {
      throw DbError(0, "bind: PostgreSQL text cannot hold a NUL character (parameter " +
                           std::to_string(index) + ")");
    }
    // Untyped (like a quoted literal): PostgreSQL takes the type the context wants.
    set(index, 0, std::string(text), 0);
  }
  void bind_blob(int index, std::span<const std::uint8_t> bytes) override {
    set(index, kByteaOid, std::string(bytes.begin(), bytes.end()), 1);
  }
  void bind_null(int index) override {
    check_index(index);
    params_[static_cast<std::size_t>(index - 1)] = Param{};
  }

  bool step() override;

  void reset() override {
    result_.reset();
    executed_ = false;
    for (auto& p : params_)
      p = Param{};
  }

  int columns() const override { return result_ ? PQnfields(result_.get()) : 0; }
  bool is_null(int column) const override {
    return !in_row(column) || PQgetisnull(result_.get(), row_, column);
  }
  std::int64_t int64(int column) const override {
    if (is_null(column)) return 0;
    const char* value = PQgetvalue(result_.get(), row_, column);
    if (PQftype(result_.get(), column) == kBoolOid) return value[0] == 't' ? 1 : 0;
    std::int64_t out = 0;
    const char* end = value + std::strlen(value);
    const auto [ptr, ec] = std::from_chars(value, end, out);
    if (ec == std::errc{} && ptr == end) return out;
    // Numeric or float text: saturated, as SQLite converts an out-of-range real.
    const double real = std::strtod(value, nullptr);
    if (!(real > -9.2233720368547758e18)) return std::numeric_limits<std::int64_t>::min();
    if (!(real < 9.2233720368547758e18)) return std::numeric_limits<std::int64_t>::max();
    return static_cast<std::int64_t>(real);
  }
  double real(int column) const override {
    if (is_null(column)) return 0.0;
    return std::strtod(PQgetvalue(result_.get(), row_, column), nullptr);
  }
  std::string text(int column) const override {
    if (is_null(column)) return "";
    if (PQftype(result_.get(), column) == kByteaOid) {
      const auto bytes = blob(column);
      return std::string(bytes.begin(), bytes.end());
    }
    return std::string(PQgetvalue(result_.get(), row_, column),
                       static_cast<std::size_t>(PQgetlength(result_.get(), row_, column)));
  }
  std::vector<std::uint8_t> blob(int column) const override {
    if (is_null(column)) return {};
    const auto* value =
        reinterpret_cast<const unsigned char*>(PQgetvalue(result_.get(), row_, column));
    if (PQftype(result_.get(), column) != kByteaOid) {
      return std::vector<std::uint8_t>(value, value + PQgetlength(result_.get(), row_, column));
    }
    std::size_t length = 0;
    unsigned char* raw = PQunescapeBytea(value, &length);
    if (!raw) throw DbError(0, "blob: cannot decode a bytea value (out of memory)");
    std::vector<std::uint8_t> out(raw, raw + length);
    PQfreemem(raw);
    return out;
  }

 private:
  struct Param {
    bool null = true;
    Oid type = 0;
    std::string value;
    int format = 0;  // 0 text, 1 binary
  };

  void check_index(int index) const {
    if (index < 1 || static_cast<std::size_t>(index) > params_.size()) {
      throw DbError(0, "bind: parameter " + std::to_string(index) + " is out of range (the " +
                           "statement has " + std::to_string(params_.size()) + ")");
    }
  }
  void set(int index, Oid type, std::string value, int format) {
    check_index(index);
    params_[static_cast<std::size_t>(index - 1)] = Param{false, type, std::move(value), format};
  }
  bool in_row(int column) const {
    return result_ && row_ >= 0 && row_ < rows_ && column >= 0 && column < PQnfields(result_.get());
  }

  PgConnection& owner_;
  PGconn* conn_;
  std::string sql_;
  std::vector<Param> params_;
  Result result_;
  bool executed_ = false;
  int row_ = -1;
  int rows_ = 0;
};

class PgConnection final : public Connection {
 public:
  explicit PgConnection(const std::string& uri) : conn_(PQconnectdb(uri.c_str())) {
    if (!conn_ || PQstatus(conn_) != CONNECTION_OK) {
      const std::string why = conn_ ? trimmed(PQerrorMessage(conn_)) : "out of memory";
      PQfinish(conn_);
      throw DbError(0, "cannot open database " + DatabaseUrl{Dialect::postgresql, uri}.redacted() +
                           ": " + why);
    }
    // Notices (e.g. "relation already exists, skipping") are not errors: keep them off stderr.
    PQsetNoticeProcessor(
        conn_, [](void*, const char*) {}, nullptr);
    try {
      // lock_timeout mirrors SQLite's busy timeout: a writer waits 5 s for a lock, then fails.
      exec(
          "SET client_encoding = 'UTF8'; SET client_min_messages = warning; SET lock_timeout = "
          "5000");
    } catch (...) {
      PQfinish(conn_);
      throw;
    }
  }
  ~PgConnection() override { PQfinish(conn_); }
  PgConnection(const PgConnection&) = delete;
  PgConnection& operator=(const PgConnection&) = delete;

  Dialect dialect() const override { return Dialect::postgresql; }

  void exec(std::string_view sql) override {
    const std::string text(sql);
    Result result(PQexec(conn_, text.c_str()));
    const auto status = PQresultStatus(result.get());
    if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) {
      throw_result_error(conn_, result.get(), "exec");
    }
    note_changes(result.get());
  }

  std::unique_ptr<Cursor> prepare(std::string_view sql) override {
    return std::make_unique<PgCursor>(*this, conn_, sql);
  }
  int changes() const override { return changes_; }
  bool in_transaction() const override { return PQtransactionStatus(conn_) != PQTRANS_IDLE; }
  bool usable() const override { return PQstatus(conn_) == CONNECTION_OK; }
  void* native_handle() const override { return conn_; }

  // Like sqlite3_changes: the rows of the last INSERT, UPDATE or DELETE (a SELECT leaves it).
  void note_changes(const PGresult* result) {
    auto* r = const_cast<PGresult*>(result);
    const std::string_view status = PQcmdStatus(r);
    if (status.starts_with("INSERT") || status.starts_with("UPDATE") ||
        status.starts_with("DELETE")) {
      changes_ = std::atoi(PQcmdTuples(r));
    }
  }

 private:
  PGconn* conn_;
  int changes_ = 0;
};

bool PgCursor::step() {
  if (!executed_) {
    std::vector<Oid> types(params_.size());
    std::vector<const char*> values(params_.size());
    std::vector<int> lengths(params_.size());
    std::vector<int> formats(params_.size());
    for (std::size_t i = 0; i < params_.size(); ++i) {
      types[i] = params_[i].type;
      values[i] = params_[i].null ? nullptr : params_[i].value.c_str();
      lengths[i] = static_cast<int>(params_[i].value.size());
      formats[i] = params_[i].format;
    }
    Result result(PQexecParams(conn_, sql_.c_str(), static_cast<int>(params_.size()), types.data(),
                               values.data(), lengths.data(), formats.data(), 0));
    const auto status = PQresultStatus(result.get());
    if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) {
      throw_result_error(conn_, result.get(), "step");
    }
    owner_.note_changes(result.get());
    rows_ = status == PGRES_TUPLES_OK ? PQntuples(result.get()) : 0;
    result_ = std::move(result);
    executed_ = true;
    row_ = -1;
  }
  if (++row_ < rows_) return true;
  // Done: a further step runs the statement again with the same bindings, as SQLite's does.
  executed_ = false;
  return false;
}

}  // namespace

std::unique_ptr<Connection> open_postgresql(const std::string& uri) {
  return std::make_unique<PgConnection>(uri);
}

}  // namespace incise::db::detail
