#pragma once
// Where the data lives, as the server's --database flag names it:
//   sqlite:PATH                      an SQLite file (the embedded default)
//   postgresql://USER@HOST:PORT/DB   a PostgreSQL server, in libpq's URI form (postgres:// too)
#include <filesystem>
#include <string>
#include <string_view>

namespace incise::db {

enum class Dialect { sqlite, postgresql };

struct DatabaseUrl {
  Dialect dialect = Dialect::sqlite;
  std::string target;  // the SQLite file's path, or the whole libpq URI

  // Throws std::invalid_argument with a sentence naming what is wrong.
  static DatabaseUrl parse(std::string_view text);
  static DatabaseUrl sqlite(const std::filesystem::path& path);
  // The URL with any password replaced by "***", for logs and error messages.
  std::string redacted() const;
};

}  // namespace incise::db
