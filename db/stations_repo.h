#pragma once
// Haptic stations. Each has a secret token its agent presents; only the token's hash is stored.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "db/database.h"

namespace incise::db {

struct Station {
  std::int64_t id = 0;
  std::string name;
  std::string location;
  std::int64_t created_at = 0;
  // What it can run ("bench", "laparoscopy", "arthroscopy"; curriculum Task::station_kind): its
  // devices and scenes. "" = not declared. db/ stores it; the curriculum's rules compare it.
  std::string kind;
  // Set when an admin retired it: kept for its history, no longer booked, started or connected.
  std::optional<std::int64_t> retired_at;
  bool retired() const { return retired_at.has_value(); }
};

class StationsRepo {
 public:
  explicit StationsRepo(Database& db) : db_(db) {}

  // Creates the station with the given agent token (random_token() for a new one).
  // Throws Conflict when the name is taken.
  Station create(std::string_view name, std::string_view location, std::string_view token,
                 std::int64_t now, std::string_view kind = "");
  std::optional<Station> find(std::int64_t id);
  std::optional<Station> find_by_token(std::string_view token);
  std::vector<Station> list();

  // The station's calibration as stored (JSON text, devices/kinematics.h; "" = the default).
  // The caller validates it: db/ knows nothing of devices. Throws NotFound for an unknown id.
  std::string calibration(std::int64_t id);
  void set_calibration(std::int64_t id, std::string_view json_text);
  // Throws NotFound for an unknown id.
  void set_kind(std::int64_t id, std::string_view kind);
  // Retires the station (at = the moment) or returns it to service (nullopt). Throws NotFound.
  void set_retired(std::int64_t id, std::optional<std::int64_t> at);

 private:
  Database& db_;
};

}  // namespace incise::db
