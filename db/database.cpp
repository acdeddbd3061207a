#include "db/database.h"

#include "db/connection.h"
#include "db/statement.h"

namespace incise::db {

Database::Database(const std::filesystem::path& path) : connection_(detail::open_sqlite(path)) {}

Database::Database(const DatabaseUrl& url)
    : connection_(url.dialect == Dialect::sqlite ? detail::open_sqlite(url.target)
                                                 : detail::open_postgresql(url.target)) {}

Database::~Database() = default;

Dialect Database::dialect() const {
  return connection_->dialect();
}

void Database::exec(std::string_view sql) {
  connection_->exec(sql);
}

Statement Database::prepare(std::string_view sql) {
  return Statement(connection_->prepare(sql));
}

int Database::changes() const {
  return connection_->changes();
}

bool Database::in_transaction() const {
  return connection_->in_transaction();
}

bool Database::usable() const {
  return connection_->usable();
}

sqlite3* Database::handle() const {
  return connection_->dialect() == Dialect::sqlite
             ? static_cast<sqlite3*>(connection_->native_handle())
             : nullptr;
}

}  // namespace incise::db
