#pragma once
// The API's JSON shapes of stored records (docs/api.md). One place, so every endpoint that
// returns a booking returns the same booking.
#include <nlohmann/json.hpp>

#include "db/bookings_repo.h"
#include "db/curricula_repo.h"
#include "db/stations_repo.h"
#include "db/training_repo.h"
#include "db/users_repo.h"

namespace incise::server {

nlohmann::json to_json(const db::User& user);
nlohmann::json to_json(const db::Station& station, bool online);
nlohmann::json to_json(const db::Booking& booking);
nlohmann::json to_json(const db::SessionRecord& session);
nlohmann::json to_json(const db::RecordingRecord& recording);
nlohmann::json to_json(const db::ScoreRecord& score);
nlohmann::json to_json(const db::CurriculumRecord& curriculum);

}  // namespace incise::server
