// Stations declare what they can run and tasks name the kind they need: the station's task list
// (GET /api/stations/{id}/tasks), the refusal of a task the station cannot run, and an admin
// changing a station's kind (PATCH /api/stations/{id}), through the router.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "api_test_app.h"
#include "db/audit_repo.h"
#include "db/bookings_repo.h"
#include "db/stations_repo.h"
#include "server/demo_data.h"

namespace incise::server::test {
namespace {

class StationOfferApi : public ApiTest {
 protected:
  std::int64_t station_named(const std::string& name) {
    for (const auto& s : db::StationsRepo(db()).list())
      if (s.name == name) return s.id;
    ADD_FAILURE() << "no station " << name;
    return 0;
  }
  std::vector<std::string> task_keys(std::int64_t station, Who who) {
    const auto body =
        json_of(get("/api/stations/" + std::to_string(station) + "/tasks", session_of(who)));
    std::vector<std::string> keys;
    for (const auto& t : body["tasks"])
      keys.push_back(t["key"]);
    return keys;
  }
  Response patch(const std::string& target, const nlohmann::json& body, const std::string& token) {
    return call({http::verb::patch, target, body.dump(), token});
  }
};

TEST_F(StationOfferApi, EachDemoStationOffersOnlyTheTasksOfItsKind) {
  const auto bench = demo_station_id();
  const auto surgical = station_named(kDemoSurgicalStationName);
  const auto knee = station_named(kDemoArthroscopyStationName);
  EXPECT_EQ(task_keys(bench, Who::trainee),
            (std::vector<std::string>{"palpation", "bimanual_palpation"}));
  EXPECT_EQ(task_keys(surgical, Who::trainee), std::vector<std::string>{"liver_cut"});
  EXPECT_EQ(task_keys(knee, Who::instructor),
            (std::vector<std::string>{"knee_tour", "knee_meniscectomy"}));
  // The trainee sees what locks a task; staff may run any.
  const auto trainee = json_of(
      get("/api/stations/" + std::to_string(surgical) + "/tasks", session_of(Who::trainee)));
  EXPECT_EQ(trainee["station"]["kind"], "laparoscopy");
  EXPECT_NE(trainee["tasks"][0]["locked_reason"].get<std::string>().find("is locked"),
            std::string::npos);
  const auto staff = json_of(
      get("/api/stations/" + std::to_string(surgical) + "/tasks", session_of(Who::instructor)));
  EXPECT_EQ(staff["tasks"][0]["locked_reason"], "");
  EXPECT_TRUE(is_error(get("/api/stations/9999/tasks", session_of(Who::trainee)),
                       http::status::not_found, "station 9999 does not exist"));
}

// The issue's case: palpation at the Surgical station is refused, whatever the browser offers,
// and nothing is stored.
TEST_F(StationOfferApi, ATaskTheStationCannotRunIsRefusedWith409) {
  const auto surgical = station_named(kDemoSurgicalStationName);
  const auto trainee = user_id("trainee");
  db::BookingsRepo(db()).create(surgical, trainee, now() - 60, now() + 3600, now() - 60);
  const auto sessions = count("sessions");
  EXPECT_TRUE(is_error(post("/api/sessions", {{"station_id", surgical}, {"task", "palpation"}},
                            session_of(Who::trainee)),
                       http::status::conflict,
                       "task \"Palpation\" needs a bench station; Surgical station is a "
                       "laparoscopy station"));
  // Staff are held to the station's kind too: the scene needs the station's devices.
  EXPECT_TRUE(is_error(post("/api/sessions", {{"station_id", surgical}, {"task", "palpation"}},
                            session_of(Who::instructor)),
                       http::status::conflict));
  EXPECT_EQ(count("sessions"), sessions);
}

TEST_F(StationOfferApi, AnAdminSetsAStationsKindAndTheAuditKeepsBeforeAndAfter) {
  const auto bench = demo_station_id();
  const std::string path = "/api/stations/" + std::to_string(bench);
  const auto audits = count("audit_log");
  EXPECT_TRUE(is_error(patch(path, {{"kind", "Lap scope"}}, session_of(Who::admin)),
                       http::status::unprocessable_entity));
  EXPECT_TRUE(
      is_error(patch(path, {{"kind", "laparoscopy"}, {"name", "x"}}, session_of(Who::admin)),
               http::status::unprocessable_entity));
  EXPECT_TRUE(is_error(patch(path, {{"kind", "laparoscopy"}}, session_of(Who::instructor)),
                       http::status::forbidden));
  EXPECT_EQ(count("audit_log"), audits);
  EXPECT_EQ(db::StationsRepo(db()).find(bench)->kind, "bench");

  const auto changed = patch(path, {{"kind", "laparoscopy"}}, session_of(Who::admin));
  ASSERT_EQ(changed.result(), http::status::ok) << changed.body();
  EXPECT_EQ(json_of(changed)["kind"], "laparoscopy");
  EXPECT_EQ(task_keys(bench, Who::trainee), std::vector<std::string>{"liver_cut"});
  const auto entry = db::AuditRepo(db()).list(1).front();
  EXPECT_EQ(entry.action, "station.update");
  EXPECT_EQ(entry.detail, "Station 1");
  EXPECT_EQ(entry.before_json, R"({"kind":"bench"})");
  EXPECT_EQ(entry.after_json, R"({"kind":"laparoscopy"})");
  // "" takes the declaration back: then only tasks that name no kind fit.
  ASSERT_EQ(patch(path, {{"kind", ""}}, session_of(Who::admin)).result(), http::status::ok);
  EXPECT_TRUE(task_keys(bench, Who::trainee).empty());
}

TEST_F(StationOfferApi, ARetiredStationKeepsItsHistoryButIsNeitherBookedNorStarted) {
  const auto bench = demo_station_id();
  const std::string path = "/api/stations/" + std::to_string(bench);
  // A booking ahead holds it in service: its trainee must hear of it from a person.
  const auto booking = db::BookingsRepo(db()).create(bench, user_id("trainee"), now() + kDay,
                                                     now() + kDay + 3600, now());
  const auto audits = count("audit_log");
  EXPECT_TRUE(is_error(patch(path, {{"retired", true}}, session_of(Who::admin)),
                       http::status::conflict,
                       "Station 1 has 1 booking ahead; cancel it before retiring it"));
  EXPECT_TRUE(is_error(patch(path, {{"retired", true}}, session_of(Who::instructor)),
                       http::status::forbidden));
  EXPECT_TRUE(is_error(patch(path, nlohmann::json::object(), session_of(Who::admin)),
                       http::status::unprocessable_entity, "send kind, retired or both"));
  EXPECT_EQ(count("audit_log"), audits);
  EXPECT_FALSE(db::StationsRepo(db()).find(bench)->retired());

  db::BookingsRepo(db()).cancel(booking.id, now());
  const auto retired = patch(path, {{"retired", true}}, session_of(Who::admin));
  ASSERT_EQ(retired.result(), http::status::ok) << retired.body();
  EXPECT_EQ(json_of(retired)["retired"], true);
  const auto entry = db::AuditRepo(db()).list(1).front();
  EXPECT_EQ(entry.action, "station.retire");
  EXPECT_EQ(entry.before_json, R"({"retired":false})");
  EXPECT_EQ(entry.after_json, R"({"retired":true})");

  // Listed still (its sessions and recordings remain), but nobody books or starts it.
  bool listed = false;
  for (const auto& s : json_of(get("/api/stations", session_of(Who::trainee))))
    listed = listed || (s["id"] == bench && s["retired"] == true);
  EXPECT_TRUE(listed);
  const auto bookings = count("bookings");
  EXPECT_TRUE(is_error(post("/api/bookings",
                            {{"station_id", bench},
                             {"starts_at", "2030-01-09T10:00:00Z"},
                             {"ends_at", "2030-01-09T11:00:00Z"}},
                            session_of(Who::trainee)),
                       http::status::conflict, "Station 1 is retired; book another station"));
  EXPECT_EQ(count("bookings"), bookings);
  const auto sessions = count("sessions");
  EXPECT_TRUE(is_error(post("/api/sessions", {{"station_id", bench}, {"task", "palpation"}},
                            session_of(Who::instructor)),
                       http::status::conflict, "Station 1 is retired"));
  EXPECT_EQ(count("sessions"), sessions);

  // Back in service.
  ASSERT_EQ(patch(path, {{"retired", false}}, session_of(Who::admin)).result(), http::status::ok);
  EXPECT_EQ(db::AuditRepo(db()).list(1).front().action, "station.reinstate");
  EXPECT_FALSE(db::StationsRepo(db()).find(bench)->retired());
}

TEST_F(StationOfferApi, OnlyStaffStartExpertRuns) {
  const auto sessions = count("sessions");
  EXPECT_TRUE(
      is_error(post("/api/sessions",
                    {{"station_id", demo_station_id()}, {"task", "palpation"}, {"expert", true}},
                    session_of(Who::trainee)),
               http::status::forbidden, "expert runs are instructors' or admins'"));
  EXPECT_TRUE(
      is_error(post("/api/sessions",
                    {{"station_id", demo_station_id()}, {"task", "palpation"}, {"expert", 1}},
                    session_of(Who::instructor)),
               http::status::unprocessable_entity));
  EXPECT_EQ(count("sessions"), sessions);
}

}  // namespace
}  // namespace incise::server::test
