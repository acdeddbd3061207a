#include "db/stations_repo.h"

#include "db/password.h"
#include "db/statement.h"

namespace incise::db {

namespace {
constexpr const char* kSelect =
    "SELECT id, name, location, created_at, kind, retired_at FROM stations";

Station read_station(const Statement& q) {
  return Station{q.int64(0), q.text(1), q.text(2), q.int64(3), q.text(4), q.optional_int64(5)};
}
}  // namespace

Station StationsRepo::create(std::string_view name, std::string_view location,
                             std::string_view token, std::int64_t now, std::string_view kind) {
  // ON CONFLICT (name) DO NOTHING rather than catching the constraint error: on PostgreSQL a
  // failed statement would spoil the caller's transaction. A repeated token still throws.
  auto q = db_.prepare(
      "INSERT INTO stations (name, location, token_hash, created_at, kind) VALUES (?, ?, ?, ?, ?) "
      "ON CONFLICT (name) DO NOTHING RETURNING id");
  q.bind(1, name).bind(2, location).bind_blob(3, token_hash(token)).bind(4, now).bind(5, kind);
  if (!q.step()) throw Conflict("a station named '" + std::string(name) + "' already exists");
  const std::int64_t id = q.int64(0);
  q.run();
  return Station{id,  std::string(name), std::string(location),
                 now, std::string(kind), std::nullopt};
}

std::optional<Station> StationsRepo::find(std::int64_t id) {
  auto q = db_.prepare(std::string(kSelect) + " WHERE id = ?");
  q.bind(1, id);
  if (!q.step()) return std::nullopt;
  return read_station(q);
}

std::optional<Station> StationsRepo::find_by_token(std::string_view token) {
  auto q = db_.prepare(std::string(kSelect) + " WHERE token_hash = ?");
  q.bind_blob(1, token_hash(token));
  if (!q.step()) return std::nullopt;
  return read_station(q);
}

std::vector<Station> StationsRepo::list() {
  auto q = db_.prepare(std::string(kSelect) + " ORDER BY name");
  std::vector<Station> out;
  while (q.step())
    out.push_back(read_station(q));
  return out;
}

std::string StationsRepo::calibration(std::int64_t id) {
  auto q = db_.prepare("SELECT calibration FROM stations WHERE id = ?");
  q.bind(1, id);
  if (!q.step()) throw NotFound("station " + std::to_string(id) + " not found");
  return q.text(0);
}

void StationsRepo::set_calibration(std::int64_t id, std::string_view json_text) {
  auto q = db_.prepare("UPDATE stations SET calibration = ? WHERE id = ?");
  q.bind(1, json_text).bind(2, id).run();
  if (db_.changes() == 0) throw NotFound("station " + std::to_string(id) + " not found");
}

void StationsRepo::set_kind(std::int64_t id, std::string_view kind) {
  auto q = db_.prepare("UPDATE stations SET kind = ? WHERE id = ?");
  q.bind(1, kind).bind(2, id).run();
  if (db_.changes() == 0) throw NotFound("station " + std::to_string(id) + " not found");
}

void StationsRepo::set_retired(std::int64_t id, std::optional<std::int64_t> at) {
  auto q = db_.prepare("UPDATE stations SET retired_at = ? WHERE id = ?");
  q.bind(1, at).bind(2, id).run();
  if (db_.changes() == 0) throw NotFound("station " + std::to_string(id) + " not found");
}

}  // namespace incise::db
