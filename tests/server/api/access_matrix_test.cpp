// The access-control matrix (docs/api.md): every REST endpoint x every role x own or
// another trainee's data, through the router with a real SQLite file. "allow" means the role
// gets past the access check (any status but 401 and 403); "deny" means 401 without a login and
// 403 with one. The live view WebSockets have their own tests (integration).

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "api_test_app.h"
#include "db/bookings_repo.h"
#include "db/training_repo.h"

namespace incise::server::test {
namespace {

// Who may: one flag per role (trainee, instructor, admin); nobody is always refused.
struct Allowed {
  bool trainee = false;
  bool instructor = false;
  bool admin = false;
  bool of(Who who) const {
    return who == Who::trainee      ? trainee
           : who == Who::instructor ? instructor
                                    : who == Who::admin && admin;
  }
};
constexpr Allowed kAnyone{true, true, true};
constexpr Allowed kStaff{false, true, true};
constexpr Allowed kAdmin{false, false, true};

struct Row {
  http::verb method;
  std::string target;
  std::string body;  // JSON, "" for none
  Allowed allowed;
};

class AccessMatrix : public ApiTest {
 protected:
  void SetUp() override {
    ApiTest::SetUp();
    db::TrainingRepo training(db());
    own_ = training.sessions(user_id("trainee")).front().id;
    const auto other = add_trainee("trainee2");
    other_trainee_ = other;
    other_ = training.create_session(other, std::nullopt, "palpation", now());
    training.set_session_state(other_, "finished", now() + 60);
    training.add_recording(other_, 60.0, now() + 60);
    training.set_session_state(own_, "finished", now() + 60);
    // A trainee the demo instructor does not teach.
    untaught_trainee_ = add_trainee("trainee3", false);
    untaught_ = training.create_session(untaught_trainee_, std::nullopt, "palpation", now());
    training.set_session_state(untaught_, "finished", now() + 60);
    training.add_recording(untaught_, 60.0, now() + 60);
    for (const auto session : {other_, untaught_})
      training.add_score(session, "peak_force_n", 3.0, "N", true, now() + 60);
  }

  void check(const Row& row) {
    for (const Who who : kEveryone) {
      const auto token = session_of(who);
      Call call(row.method, row.target, row.body.empty() ? std::nullopt : std::optional(row.body),
                token);
      const auto status = this->call(call).result_int();
      const bool allowed = who != Who::nobody && row.allowed.of(who);
      if (allowed) {
        EXPECT_NE(status, 401) << name_of(who) << " " << row.target;
        EXPECT_NE(status, 403) << name_of(who) << " " << row.target;
      } else {
        EXPECT_EQ(status, who == Who::nobody ? 401 : 403) << name_of(who) << " " << row.target;
      }
    }
  }

  std::int64_t own_ = 0;    // the demo trainee's session
  std::int64_t other_ = 0;  // another trainee's
  std::int64_t other_trainee_ = 0;
  std::int64_t untaught_ = 0;  // a session of a trainee the demo instructor does not teach
  std::int64_t untaught_trainee_ = 0;
};

TEST_F(AccessMatrix, EveryEndpointRoleAndOwnership) {
  const std::string own = std::to_string(own_);
  const std::string other = std::to_string(other_);
  const std::string untaught = std::to_string(untaught_);
  const std::string station = std::to_string(demo_station_id());
  const std::string calibration =
      R"({"devices": [{"index": 0, "kind": "pen", "mapping": {"scale": 1, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]}}]})";
  const std::vector<Row> rows = {
      {http::verb::get, "/api/me", "", kAnyone},
      // A wrong current password: 422 for everyone signed in, and nothing changes.
      {http::verb::post, "/api/me/password",
       R"({"current_password": "not it at all", "new_password": "another long one"})", kAnyone},
      {http::verb::get, "/api/users", "", kAdmin},
      {http::verb::post, "/api/users",
       R"({"username": "u1", "password": "long enough pw", "role": "trainee", "display_name": "U"})",
       kAdmin},
      {http::verb::get, "/api/stations", "", kAnyone},
      {http::verb::post, "/api/stations", R"({"name": "Bench 5"})", kAdmin},
      {http::verb::get, "/api/stations/" + station + "/calibration", "", kStaff},
      {http::verb::put, "/api/stations/" + station + "/calibration", calibration, kAdmin},
      {http::verb::get, "/api/stations/" + station + "/schedule", "", kAnyone},
      {http::verb::get, "/api/stations/" + station + "/tasks", "", kAnyone},
      {http::verb::patch, "/api/stations/" + station, R"({"kind": "bench"})", kAdmin},
      {http::verb::patch, "/api/stations/" + station, R"({"retired": false})", kAdmin},
      {http::verb::get, "/api/bookings", "", kAnyone},
      {http::verb::get, "/api/sessions", "", kAnyone},
      {http::verb::get, "/api/sessions/" + own, "", kAnyone},
      {http::verb::get, "/api/sessions/" + other, "", kStaff},
      {http::verb::get, "/api/sessions/" + own + "/annotations", "", kAnyone},
      {http::verb::get, "/api/sessions/" + other + "/annotations", "", kStaff},
      {http::verb::post, "/api/sessions/" + other + "/annotations", R"({"t_s": 1, "text": "note"})",
       kStaff},
      {http::verb::post, "/api/sessions/" + own + "/annotations", R"({"t_s": 0, "text": "note"})",
       kStaff},
      {http::verb::get, "/api/sessions/" + own + "/adjustments", "", kAnyone},
      {http::verb::get, "/api/sessions/" + other + "/adjustments", "", kStaff},
      {http::verb::post, "/api/sessions/" + other + "/adjustments",
       R"({"passed": true, "reason": "review"})", kStaff},
      {http::verb::post, "/api/sessions/" + own + "/adjustments",
       R"({"passed": true, "reason": "review"})", kStaff},
      {http::verb::get, "/api/sessions/" + own + "/review", "", kAnyone},
      {http::verb::get, "/api/sessions/" + other + "/review", "", kStaff},
      {http::verb::put, "/api/sessions/" + other + "/expert", R"({"expert": false})", kAdmin},
      {http::verb::put, "/api/sessions/" + own + "/expert", R"({"expert": false})", kAdmin},
      {http::verb::get, "/api/benchmarks", "", kAnyone},
      // Instructors see only the trainees they teach.
      {http::verb::get, "/api/sessions/" + untaught, "", kAdmin},
      {http::verb::get, "/api/sessions/" + untaught + "/review", "", kAdmin},
      {http::verb::get, "/api/sessions/" + untaught + "/annotations", "", kAdmin},
      {http::verb::post, "/api/sessions/" + untaught + "/annotations",
       R"({"t_s": 0, "text": "note"})", kAdmin},
      {http::verb::get, "/api/sessions/" + untaught + "/adjustments", "", kAdmin},
      {http::verb::post, "/api/sessions/" + untaught + "/adjustments",
       R"({"passed": true, "reason": "review"})", kAdmin},
      {http::verb::post, "/api/sessions/" + untaught + "/stop", "{}", kAdmin},
      {http::verb::get, "/api/trainees/" + std::to_string(untaught_trainee_) + "/progress", "",
       kAdmin},
      {http::verb::put, "/api/users/" + std::to_string(untaught_trainee_) + "/instructors",
       R"({"instructor_ids": []})", kAdmin},
      {http::verb::patch, "/api/users/" + std::to_string(untaught_trainee_),
       R"({"disabled": false})", kAdmin},
      {http::verb::post, "/api/users/" + std::to_string(untaught_trainee_) + "/password",
       R"({"password": "temporary-123"})", kAdmin},
      {http::verb::get, "/api/recordings", "", kAnyone},
      {http::verb::get, "/api/scores", "", kAnyone},
      {http::verb::get, "/api/exports/scores.csv", "", kAdmin},
      {http::verb::get, "/api/audit", "", kAdmin},
      {http::verb::get, "/api/progress", "", kAnyone},
      {http::verb::get, "/api/trainees/" + std::to_string(user_id("trainee")) + "/progress", "",
       kAnyone},
      {http::verb::get, "/api/trainees/" + std::to_string(other_trainee_) + "/progress", "",
       kStaff},
      {http::verb::get, "/api/trainees/progress", "", kStaff},
      {http::verb::get, "/api/metrics", "", kAnyone},
      {http::verb::get, "/api/curricula", "", kAnyone},
      {http::verb::get, "/api/curricula/1/export", "", kStaff},
  };
  for (const Row& row : rows)
    check(row);
}

// Lists are filtered, not refused: a trainee gets only their own rows, an instructor those of
// the trainees they teach, an admin everyone's.
TEST_F(AccessMatrix, ListsShowEachRoleOnlyTheDataItMaySee) {
  db::BookingsRepo bookings(db());
  const auto station = demo_station_id();
  bookings.create(station, other_trainee_, now() + kDay, now() + kDay + 3600, now());
  bookings.create(station, untaught_trainee_, now() + 2 * kDay, now() + 2 * kDay + 3600, now());
  const auto names = [&](const std::string& path, Who who) {
    std::set<std::string> seen;
    for (const auto& row : json_of(get(path, session_of(who)))) {
      seen.insert(row.contains("trainee") ? row["trainee"].get<std::string>()
                                          : row["username"].get<std::string>());
    }
    return seen;
  };
  for (const char* path : {"/api/sessions", "/api/recordings", "/api/scores", "/api/bookings"}) {
    SCOPED_TRACE(path);
    const auto trainee = names(path, Who::trainee);
    EXPECT_FALSE(trainee.contains("trainee2"));
    EXPECT_FALSE(trainee.contains("trainee3"));
    const auto instructor = names(path, Who::instructor);
    EXPECT_TRUE(instructor.contains("trainee2"));
    EXPECT_FALSE(instructor.contains("trainee3"));
    EXPECT_TRUE(names(path, Who::admin).contains("trainee3"));
  }
  std::set<std::string> overview;
  for (const auto& row : json_of(get("/api/trainees/progress", session_of(Who::instructor))))
    overview.insert(row["username"].get<std::string>());
  EXPECT_TRUE(overview.contains("trainee2"));
  EXPECT_FALSE(overview.contains("trainee3"));
}

}  // namespace
}  // namespace incise::server::test
