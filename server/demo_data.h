#pragma once
#include <string_view>
// The demo data of a first run: four logins (an admin, an instructor, a trainee at the start of the
// course and one who has mastered its palpation tasks), three stations (the palpation bench, a
// surgical station with a scalpel and a grasper, an arthroscopy station with a scope and a probe),
// one curriculum, one finished practice session with its scores (so every dashboard page has
// something to show), and the resident's passing palpation attempts.
#include <string>

#include "db/database.h"

namespace incise::server {

struct DemoLogin {
  const char* username;
  const char* password;
  const char* role;
};

inline constexpr DemoLogin kDemoLogins[] = {
    {"admin", "incise-admin-demo", "admin"},
    {"instructor", "incise-instructor-demo", "instructor"},
    {"trainee", "incise-trainee-demo", "trainee"},
    // A trainee who has mastered the palpation tasks: the stations' tasks are unlocked for her.
    {"resident", "incise-resident-demo", "trainee"},
};
inline constexpr const char* kDemoStationToken = "incise-demo-station-token";
inline constexpr const char* kDemoSurgicalStationName = "Surgical station";
inline constexpr const char* kDemoSurgicalStationToken = "incise-demo-surgical-station-token";
inline constexpr const char* kDemoArthroscopyStationName = "Arthroscopy station";
inline constexpr const char* kDemoArthroscopyStationToken = "incise-demo-arthroscopy-station-token";

// Whether `token` is one of the demo stations' tokens above (public, so refused without --demo).
bool is_demo_station_token(std::string_view token);

// Seeds the demo data if the database has no users yet; returns whether it did.
bool seed_demo_data(db::Database& db, std::int64_t now);

}  // namespace incise::server
