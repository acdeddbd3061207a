// Sessions, recordings, scores, stations and curricula lists: server/api/records_api.cpp and
// stations_api.cpp through the router.
#include <gtest/gtest.h>

#include <string>

#include "api/api_test_app.h"
#include "db/training_repo.h"

namespace incise::server::test {
namespace {

class RecordsApi : public ApiTest {
 protected:
  // A second trainee with one finished session, a recording and a score (the demo trainee has
  // one session with three scores).
  void SetUp() override {
    ApiTest::SetUp();
    const auto other = add_trainee("trainee2");
    db::TrainingRepo training(db());
    const auto session = training.create_session(other, std::nullopt, "suturing", now());
    training.set_session_state(session, "running", now());
    training.set_session_state(session, "finished", now() + 60);
    training.add_recording(session, 60.0, now() + 60);
    training.add_score(session, "completion_time_s", 60.0, "s", true, now() + 60);
  }
};

TEST_F(RecordsApi, TraineesSeeOnlyTheirOwnRecords) {
  const auto token = session_of(Who::trainee);
  for (const char* path : {"/api/sessions", "/api/recordings", "/api/scores"}) {
    const auto list = json_of(get(path, token));
    ASSERT_TRUE(list.is_array()) << path;
    EXPECT_FALSE(list.empty()) << path;
    for (const auto& record : list)
      EXPECT_EQ(record["trainee"], "trainee") << path << ": " << record;
  }
}

TEST_F(RecordsApi, InstructorsAndAdminsSeeEveryone) {
  for (const Who who : {Who::instructor, Who::admin}) {
    const auto token = session_of(who);
    for (const auto& [path, size] :
         {std::pair{"/api/sessions", 2u}, std::pair{"/api/recordings", 2u},
          std::pair{"/api/scores", 4u}}) {
      const auto list = json_of(get(path, token));
      ASSERT_TRUE(list.is_array()) << path;
      EXPECT_EQ(list.size(), size) << name_of(who) << " " << path << ": " << list;
    }
  }
}

TEST_F(RecordsApi, SessionShape) {
  const auto list = json_of(get("/api/sessions", session_of(Who::instructor)));
  ASSERT_EQ(list.size(), 2u);
  for (const auto& s : list) {
    for (const char* key : {"id", "trainee_id", "trainee", "station_id", "station", "task", "state",
                            "started_at", "ended_at"}) {
      EXPECT_TRUE(s.contains(key)) << key << " in " << s;
    }
  }
  const auto& demo = list[0]["trainee"] == "trainee" ? list[0] : list[1];
  EXPECT_EQ(demo["state"], "finished");
  EXPECT_EQ(demo["station"], "Station 1");
  EXPECT_EQ(demo["started_at"], "2030-01-06T08:00:00Z");
  EXPECT_EQ(demo["ended_at"], "2030-01-06T08:01:35Z");
  const auto& other = list[0]["trainee"] == "trainee2" ? list[0] : list[1];
  EXPECT_TRUE(other["station_id"].is_null());
}

TEST_F(RecordsApi, StationsShowWhetherAnAgentIsOnline) {
  const auto list = json_of(get("/api/stations", session_of(Who::trainee)));
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0], (nlohmann::json{{"id", demo_station_id()},
                                     {"name", "Station 1"},
                                     {"location", "Skills lab, room 2"},
                                     {"online", false}}));
}

TEST_F(RecordsApi, AdminsCreateStationsWithATokenShownOnce) {
  const auto token = session_of(Who::admin);
  const auto response = post("/api/stations", {{"name", "Station 2"}}, token);
  ASSERT_EQ(response.result(), http::status::created) << response.body();
  const auto body = json_of(response);
  EXPECT_EQ(body["station"]["name"], "Station 2");
  EXPECT_EQ(body["station"]["location"], "");
  EXPECT_EQ(body["station"]["online"], false);
  EXPECT_EQ(body["token"].get<std::string>().size(), 64u);
  EXPECT_EQ(json_of(get("/api/stations", token)).size(), 2u);
  EXPECT_EQ(json_of(get("/api/stations", token)).dump().find(body["token"].get<std::string>()),
            std::string::npos);
  EXPECT_TRUE(
      is_error(post("/api/stations", {{"name", "Station 2"}}, token), http::status::conflict));
  EXPECT_TRUE(is_error(post("/api/stations", {{"name", ""}}, token),
                       http::status::unprocessable_entity, "name must be 1-64 characters"));
}

TEST_F(RecordsApi, CurriculaCarryTheirDefinition) {
  const auto list = json_of(get("/api/curricula", session_of(Who::trainee)));
  ASSERT_EQ(list.size(), 1u);
  EXPECT_TRUE(list[0]["id"].is_number_integer());
  EXPECT_TRUE(list[0]["name"].is_string());
  EXPECT_TRUE(list[0]["definition"].is_object()) << list[0];
}

TEST_F(RecordsApi, HealthNeedsNoLogin) {
  const auto response = get("/api/health", "");
  ASSERT_EQ(response.result(), http::status::ok);
  EXPECT_EQ(json_of(response)["status"], "ok");
  EXPECT_TRUE(json_of(response)["version"].is_string());
}

}  // namespace
}  // namespace incise::server::test
