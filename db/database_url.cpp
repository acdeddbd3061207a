#include "db/database_url.h"

#include <stdexcept>

namespace incise::db {

DatabaseUrl DatabaseUrl::parse(std::string_view text) {
  constexpr std::string_view sqlite_prefix = "sqlite:";
  if (text.starts_with(sqlite_prefix)) {
    const auto path = text.substr(sqlite_prefix.size());
    if (path.empty()) throw std::invalid_argument("database URL 'sqlite:' names no file");
    return sqlite(std::filesystem::path(path));
  }
  if (text.starts_with("postgresql://") || text.starts_with("postgres://")) {
    return DatabaseUrl{Dialect::postgresql, std::string(text)};
  }
  throw std::invalid_argument("database URL '" + std::string(text.substr(0, 80)) +
                              "' is neither sqlite:PATH nor postgresql://...");
}

DatabaseUrl DatabaseUrl::sqlite(const std::filesystem::path& path) {
  return DatabaseUrl{Dialect::sqlite, path.string()};
}

std::string DatabaseUrl::redacted() const {
  if (dialect == Dialect::sqlite) return "sqlite:" + target;
  std::string out = target;
  // ...?password=SECRET&...: libpq takes a password as a query parameter too.
  const auto query = out.find('?');
  for (auto at = out.find("password=", query);
       query != std::string::npos && at != std::string::npos; at = out.find("password=", at + 1)) {
    if (out[at - 1] != '?' && out[at - 1] != '&') continue;
    const auto value = at + 9;
    const auto end = out.find('&', value);
    out.replace(value, (end == std::string::npos ? out.size() : end) - value, "***");
  }
  // postgresql://user:password@host/...: hide what lies between the first ':' after the scheme
  // and the '@' of the authority.
  const auto scheme_end = out.find("://");
  const auto authority_end = out.find_first_of("/?", scheme_end + 3);
  const auto at = out.rfind('@', authority_end);
  if (at == std::string::npos || at < scheme_end) return out;
  const auto colon = out.find(':', scheme_end + 3);
  if (colon == std::string::npos || colon > at) return out;
  return out.substr(0, colon + 1) + "***" + out.substr(at);
}

}  // namespace incise::db
