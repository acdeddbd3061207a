// Sessions, recordings, scores, stations and curricula lists: server/api/records_api.cpp and
// stations_api.cpp through the router.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "api_test_app.h"
#include "curriculum/curriculum_json.h"
#include "db/auth_sessions_repo.h"
#include "db/reviews_repo.h"
#include "db/training_repo.h"
#include "server/time_text.h"

namespace incise::server::test {
namespace {

// The demo resident's mastered palpation tasks (server/demo_data.cpp): three attempts of
// palpation, scored on its two completion criteria, six metrics and never events, and three of
// the two-handed task, on its criterion and four metrics.
constexpr std::size_t kResidentSessions = 6;
constexpr std::size_t kResidentScores = 3 * (2 + 6 + 1) + 3 * (1 + 4);
// The instructor's expert runs: three of each of the five demo tasks, scored on every scored
// requirement (palpation 9, two-handed 5, liver cut 2 + 5, knee tour 2 + 3, meniscectomy 2 + 4).
constexpr std::size_t kExpertSessions = 15;
constexpr std::size_t kExpertScores = 3 * (9 + 5 + 7 + 5 + 6);

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
         {std::pair{"/api/sessions", 2u + kResidentSessions + kExpertSessions},
          std::pair{"/api/recordings", std::size_t{2}},
          std::pair{"/api/scores", 4u + kResidentScores + kExpertScores}}) {
      const auto list = json_of(get(path, token));
      ASSERT_TRUE(list.is_array()) << path;
      EXPECT_EQ(list.size(), size) << name_of(who) << " " << path << ": " << list;
    }
  }
}

TEST_F(RecordsApi, SessionShape) {
  const auto list = json_of(get("/api/sessions", session_of(Who::instructor)));
  ASSERT_EQ(list.size(), 2u + kResidentSessions + kExpertSessions);
  for (const auto& s : list) {
    for (const char* key : {"id", "trainee_id", "trainee", "station_id", "station", "task", "state",
                            "started_at", "ended_at"}) {
      EXPECT_TRUE(s.contains(key)) << key << " in " << s;
    }
  }
  const auto by = [&](const char* trainee) {
    for (const auto& s : list)
      if (s["trainee"] == trainee) return s;
    return nlohmann::json();
  };
  const auto demo = by("trainee");
  EXPECT_EQ(demo["state"], "finished");
  EXPECT_EQ(demo["station"], "Station 1");
  EXPECT_EQ(demo["started_at"], "2030-01-06T08:00:00Z");
  EXPECT_EQ(demo["ended_at"], "2030-01-06T08:01:35Z");
  const auto other = by("trainee2");
  EXPECT_TRUE(other["station_id"].is_null());
}

// The verdict of one session is the server's, by the progress rules: its scores, or the latest
// adjustment; none while it is not a finished, scored attempt.
TEST_F(RecordsApi, ASessionCarriesTheServersVerdict) {
  db::TrainingRepo training(db());
  const auto trainee = user_id("trainee");
  const auto session = training.create_session(trainee, std::nullopt, "palpation", now());
  const auto passed = [&] {
    return json_of(
        get("/api/sessions/" + std::to_string(session), session_of(Who::trainee)))["passed"];
  };
  training.set_session_state(session, "running", now());
  EXPECT_TRUE(passed().is_null());  // running
  training.set_session_state(session, "finished", now() + 60);
  EXPECT_TRUE(passed().is_null());  // finished, not scored yet
  training.add_score(session, "completion_time_s", 60.0, "s", true, now() + 60);
  EXPECT_EQ(passed(), true);
  training.add_score(session, "peak_force_n", 5.0, "N", false, now() + 60);
  EXPECT_EQ(passed(), false);  // one missed threshold fails the attempt
  db::ReviewsRepo(db()).adjust(session, user_id("instructor"), true, "sensor glitch", now() + 90);
  EXPECT_EQ(passed(), true);  // the instructor's adjustment rules
  db::ReviewsRepo(db()).adjust(session, user_id("instructor"), false, "on second look", now() + 95);
  EXPECT_EQ(passed(), false);  // the latest one
}

TEST_F(RecordsApi, StationsShowWhetherAnAgentIsOnline) {
  const auto list = json_of(get("/api/stations", session_of(Who::trainee)));
  // The demo's arthroscopy station, palpation bench and surgical station, by name.
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0]["name"], "Arthroscopy station");
  EXPECT_EQ(list[0]["online"], false);
  EXPECT_EQ(list[1], (nlohmann::json{{"id", demo_station_id()},
                                     {"name", "Station 1"},
                                     {"location", "Skills lab, room 2"},
                                     {"kind", "bench"},
                                     {"retired", false},
                                     {"online", false}}));
  EXPECT_EQ(list[2]["name"], "Surgical station");
  EXPECT_EQ(list[2]["online"], false);
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
  EXPECT_EQ(json_of(get("/api/stations", token)).size(), 4u);  // the demo's three and this one
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

// A minimal RFC 4180 reader for the test: rows of fields, quotes undone.
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows(1);
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      rows.back().push_back(std::move(field));
      field.clear();
    } else if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') {
      rows.back().push_back(std::move(field));
      field.clear();
      rows.emplace_back();
      ++i;
    } else {
      field += c;
    }
  }
  if (rows.back().empty()) rows.pop_back();
  return rows;
}

TEST_F(RecordsApi, AdminsExportEveryScoreAsCsvThatReadsBackExactly) {
  // A task name a spreadsheet would trip over: a comma, quotes, a line break, a formula.
  db::TrainingRepo training(db());
  const auto other = add_trainee("trainee3");
  const std::string task = "=HYPERLINK(\"x\"), cut \"A\"\nline 2";
  const auto session = training.create_session(other, std::nullopt, task, now());
  training.add_score(session, "peak_force_n", 0.1 + 0.2, "N", false, now() + 5);

  for (const Who who : {Who::trainee, Who::instructor}) {
    EXPECT_EQ(get("/api/exports/scores.csv", session_of(who)).result_int(), 403) << name_of(who);
  }
  const auto response = get("/api/exports/scores.csv", session_of(Who::admin));
  ASSERT_EQ(response.result_int(), 200);
  EXPECT_EQ(response[http::field::content_type], "text/csv; charset=utf-8");
  EXPECT_EQ(response["Content-Disposition"], "attachment; filename=\"incise-scores.csv\"");
  const auto rows = parse_csv(response.body());
  // The header, the demo trainee's 3, the resident's, the experts', trainee2's 1, this one.
  ASSERT_EQ(rows.size(), 1u + 5u + kResidentScores + kExpertScores);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"score_id", "session_id", "trainee", "task",
                                               "metric", "value", "unit", "passed", "created_at"}));
  const auto scores = training.scores();
  ASSERT_EQ(scores.size(), 5u + kResidentScores + kExpertScores);
  for (std::size_t i = 0; i < scores.size(); ++i) {
    const auto& row = rows[i + 1];
    ASSERT_EQ(row.size(), 9u) << i;
    EXPECT_EQ(row[0], std::to_string(scores[i].id));
    EXPECT_EQ(row[1], std::to_string(scores[i].session_id));
    EXPECT_EQ(row[2], scores[i].trainee);
    // A formula-looking text starts with an apostrophe; everything else is as stored.
    const bool formula = scores[i].task.front() == '=';
    EXPECT_EQ(row[3], formula ? "'" + scores[i].task : scores[i].task);
    EXPECT_EQ(row[4], scores[i].metric);
    EXPECT_EQ(std::stod(row[5]), scores[i].value);  // %.17g: the double exactly
    EXPECT_EQ(row[6], scores[i].unit);
    EXPECT_EQ(row[7], scores[i].passed ? "true" : "false");
    EXPECT_EQ(row[8], format_utc(scores[i].created_at));
  }
  // The export is in the audit log.
  EXPECT_EQ(count("audit_log WHERE action = 'export.scores'"), 1);
}

TEST_F(RecordsApi, OnlyAdminsReadTheAuditLogNewestFirst) {
  for (const Who who : {Who::trainee, Who::instructor}) {
    EXPECT_EQ(get("/api/audit", session_of(who)).result_int(), 403) << name_of(who);
  }
  const auto admin = session_of(Who::admin);
  // Two audited actions by the admin: a station, then an export.
  ASSERT_EQ(post("/api/stations", {{"name", "Bench 9"}}, admin).result_int(), 201);
  ASSERT_EQ(get("/api/exports/scores.csv", admin).result_int(), 200);
  const auto entries = json_of(get("/api/audit", admin));
  ASSERT_TRUE(entries.is_array());
  ASSERT_GE(entries.size(), 2u);
  EXPECT_EQ(entries[0]["action"], "export.scores");
  EXPECT_EQ(entries[1]["action"], "station.create");
  EXPECT_EQ(entries[1]["detail"], "Bench 9");
  EXPECT_EQ(entries[0]["user_id"], entries[1]["user_id"]);
  EXPECT_GT(entries[0]["id"].get<std::int64_t>(), entries[1]["id"].get<std::int64_t>());
  EXPECT_TRUE(parse_utc(entries[0]["at"].get<std::string>()).has_value());
}

// The demo curriculum: palpation (3 consecutive passes), then two-handed palpation (needs it).
TEST_F(RecordsApi, ProgressUnlocksTheNextTaskAfterEnoughConsecutivePasses) {
  const auto tess = add_trainee("tess");
  db::TrainingRepo training(db());
  std::int64_t t = now();
  // One finished palpation attempt, every metric passed or not.
  const auto attempt = [&](bool pass) {
    const auto session = training.create_session(tess, std::nullopt, "palpation", t);
    training.set_session_state(session, "finished", ++t);
    training.add_score(session, "completion_time_s", 60.0, "s", true, t);
    training.add_score(session, "peak_force_n", 3.0, "N", pass, t);
  };
  const auto token = db::AuthSessionsRepo(db()).create(tess, now(), 3600);
  const auto task_of = [&](const std::string& key) {
    const auto progress = json_of(get("/api/progress", token));
    for (const auto& task : progress["tasks"])
      if (task["key"] == key) return task;
    return nlohmann::json();
  };
  EXPECT_TRUE(task_of("palpation")["unlocked"].get<bool>());
  EXPECT_FALSE(task_of("bimanual_palpation")["unlocked"].get<bool>());
  EXPECT_EQ(task_of("bimanual_palpation")["missing_prerequisites"],
            nlohmann::json::array({"palpation"}));
  const std::string locked = "task \"Two-handed palpation\" is locked: master \"Palpation\" first";
  EXPECT_EQ(task_of("bimanual_palpation")["locked_reason"], locked);
  EXPECT_EQ(task_of("palpation")["locked_reason"], "");
  // The server refuses to start a locked task, whatever the browser offers, and stores nothing.
  const nlohmann::json start = {{"station_id", demo_station_id()}, {"task", "bimanual_palpation"}};
  const auto sessions_before = training.sessions(tess).size();
  EXPECT_TRUE(is_error(post("/api/sessions", start, token), http::status::conflict, locked));
  EXPECT_EQ(training.sessions(tess).size(), sessions_before);

  attempt(true);
  attempt(true);
  attempt(false);  // a failure starts the count again
  attempt(true);
  attempt(true);
  auto palpation = task_of("palpation");
  EXPECT_EQ(palpation["attempts"], 5);
  EXPECT_EQ(palpation["passed_attempts"], 4);
  EXPECT_EQ(palpation["consecutive_passes"], 2);
  EXPECT_EQ(palpation["required_passes"], 3);
  EXPECT_FALSE(palpation["mastered"].get<bool>());
  EXPECT_FALSE(task_of("bimanual_palpation")["unlocked"].get<bool>());

  attempt(true);  // the third in a row
  palpation = task_of("palpation");
  EXPECT_EQ(palpation["consecutive_passes"], 3);
  EXPECT_TRUE(palpation["mastered"].get<bool>());
  const auto next = task_of("bimanual_palpation");
  EXPECT_TRUE(next["unlocked"].get<bool>());
  EXPECT_EQ(next["prerequisites"], nlohmann::json::array({"palpation"}));
  // Unlocked, the same start gets past the lock to the next rule (tess has no booking).
  EXPECT_TRUE(
      is_error(post("/api/sessions", start, token), http::status::forbidden,
               "no booking of station " + std::to_string(demo_station_id()) + " covers now"));

  // Instructors read any trainee's; a trainee only their own.
  const auto path = "/api/trainees/" + std::to_string(tess) + "/progress";
  EXPECT_EQ(json_of(get(path, session_of(Who::instructor)))["tasks"],
            json_of(get("/api/progress", token))["tasks"]);
  EXPECT_EQ(get(path, session_of(Who::trainee)).result_int(), 403);
  EXPECT_EQ(get("/api/trainees/999999/progress", session_of(Who::admin)).result_int(), 404);
  // An instructor cannot tell an unknown id from a trainee they do not teach.
  const auto untaught = add_trainee("una", false);
  for (const auto id : {std::int64_t{999999}, untaught}) {
    EXPECT_TRUE(is_error(
        get("/api/trainees/" + std::to_string(id) + "/progress", session_of(Who::instructor)),
        http::status::forbidden, "you do not teach trainee " + std::to_string(id)));
  }
  // The overview has every trainee's, tess's the same as her own view.
  const auto overview = json_of(get("/api/trainees/progress", session_of(Who::instructor)));
  ASSERT_TRUE(overview.is_array());
  bool found = false;
  for (const auto& row : overview) {
    if (row["username"] != "tess") continue;
    found = true;
    EXPECT_EQ(row["tasks"], json_of(get("/api/progress", token))["tasks"]);
  }
  EXPECT_TRUE(found);
}

TEST_F(RecordsApi, AdminsImportEditAndExportCurriculaWithPreciseErrors) {
  const auto admin = session_of(Who::admin);
  const auto demo = json_of(get("/api/curricula", admin))[0];
  auto definition = demo["definition"];
  definition["name"] = "Advanced skills";

  for (const Who who : {Who::trainee, Who::instructor}) {
    EXPECT_EQ(post("/api/curricula", definition, session_of(who)).result_int(), 403);
  }
  // A bad file is refused with the path of its first problem, and nothing is stored.
  auto bad = definition;
  bad["modules"][0]["tasks"][1]["metrics"][0]["threshold"]["op"] = "<";
  const auto refused = post("/api/curricula", bad, admin);
  EXPECT_TRUE(is_error(refused, http::status::unprocessable_entity,
                       "modules[0].tasks[1].metrics[0].threshold.op: must be \"<=\" or \">=\""))
      << refused.body();
  EXPECT_EQ(count("curricula"), 1);

  const auto created = post("/api/curricula", definition, admin);
  ASSERT_EQ(created.result_int(), 201) << created.body();
  const auto id = json_of(created)["id"].get<std::int64_t>();
  EXPECT_EQ(post("/api/curricula", definition, admin).result_int(), 409);  // the name is taken

  // Edit a threshold: the export is the edited definition, and it imports back as it is.
  definition["modules"][0]["tasks"][0]["metrics"][2]["threshold"]["value"] = 3.5;
  const auto path = "/api/curricula/" + std::to_string(id);
  ASSERT_EQ(put(path, definition, admin).result_int(), 200);
  const auto exported = get(path + "/export", session_of(Who::instructor));
  ASSERT_EQ(exported.result_int(), 200);
  EXPECT_EQ(exported["Content-Disposition"],
            "attachment; filename=\"curriculum-" + std::to_string(id) + ".json\"");
  const auto file = json_of(exported);
  EXPECT_EQ(file["modules"][0]["tasks"][0]["metrics"][2]["threshold"]["value"], 3.5);
  EXPECT_EQ(curriculum::parse_curriculum(file), curriculum::parse_curriculum(definition));
  EXPECT_EQ(put("/api/curricula/999999", definition, admin).result_int(), 404);
  EXPECT_EQ(count("audit_log WHERE action IN ('curriculum.import', 'curriculum.update')"), 2);
}

TEST_F(RecordsApi, TheMetricCatalogueDefinesEveryMetricOnceWithItsUnit) {
  EXPECT_EQ(get("/api/metrics", "").result_int(), 401);
  const auto metrics = json_of(get("/api/metrics", session_of(Who::trainee)));
  ASSERT_TRUE(metrics.is_array());
  std::set<std::string> keys;
  for (const auto& m : metrics) {
    EXPECT_TRUE(keys.insert(m["key"].get<std::string>()).second) << "twice: " << m;
    EXPECT_FALSE(m["definition"].get<std::string>().empty()) << m;
    EXPECT_TRUE(m.contains("unit")) << m;
  }
  // The demo tasks' metrics, each hand's motion metrics, the bimanual ones, the event metrics and
  // the depth along the shaft are all defined.
  for (const char* key :
       {"completion_time_s", "path_length_m", "peak_force_n", "rms_force_n", "contact_time_s",
        "economy_of_motion", "log_dimensionless_jerk", "idle_time_s", "path_length_m_left",
        "bimanual_dexterity", "protected_collisions", "never_events", "tissue_damage_ns",
        "targets_fraction", "max_depth_m", "mean_depth_m_left", "sim_damage_index",
        "sim_peak_strain"}) {
    EXPECT_TRUE(keys.contains(key)) << key;
  }
  // Every metric the demo curriculum scores is in the catalogue, with the task's unit.
  const auto curricula = json_of(get("/api/curricula", session_of(Who::trainee)));
  for (const auto& module : curricula[0]["definition"]["modules"]) {
    for (const auto& task : module["tasks"]) {
      for (const auto& required : task["metrics"]) {
        const auto it = std::find_if(metrics.begin(), metrics.end(), [&](const nlohmann::json& m) {
          return m["key"] == required["key"];
        });
        ASSERT_NE(it, metrics.end()) << required;
        EXPECT_EQ((*it)["unit"], required["unit"]) << required;
      }
    }
  }
}

TEST_F(RecordsApi, InstructorsAnnotateAndAdjustAnAttemptWhichItsTraineeSees) {
  db::TrainingRepo training(db());
  const auto tess = add_trainee("tess");
  const auto tess_token = db::AuthSessionsRepo(db()).create(tess, now(), 3600);
  // A finished palpation attempt of 60 s that failed its peak force.
  const auto session = training.create_session(tess, std::nullopt, "palpation", now());
  training.set_session_state(session, "finished", now() + 60);
  training.add_recording(session, 60.0, now() + 60);
  training.add_score(session, "peak_force_n", 4.5, "N", false, now() + 60);
  const auto base = "/api/sessions/" + std::to_string(session);
  const auto instructor = session_of(Who::instructor);

  // Annotations: instructors write, at a time within the recording.
  const auto added =
      post(base + "/annotations", {{"t_s", 12.5}, {"text", "too much force here"}}, instructor);
  ASSERT_EQ(added.result_int(), 201) << added.body();
  ASSERT_EQ(
      post(base + "/annotations", {{"t_s", 3}, {"text", "good approach"}}, instructor).result_int(),
      201);
  EXPECT_TRUE(is_error(post(base + "/annotations", {{"t_s", 61}, {"text", "x"}}, instructor),
                       http::status::unprocessable_entity,
                       "t_s must be within the recording, 0 to 60.000000 s"));
  EXPECT_TRUE(is_error(post(base + "/annotations", {{"t_s", 1}, {"text", ""}}, instructor),
                       http::status::unprocessable_entity, "text must be 1-2000 characters"));
  EXPECT_EQ(post(base + "/annotations", {{"t_s", 1}, {"text", "mine"}}, tess_token).result_int(),
            403);
  // The trainee reads them in time order; another trainee may not.
  const auto notes = json_of(get(base + "/annotations", tess_token));
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_EQ(notes[0]["text"], "good approach");
  EXPECT_EQ(notes[1]["t_s"], 12.5);
  EXPECT_EQ(notes[1]["author"], "instructor");
  EXPECT_EQ(get(base + "/annotations", session_of(Who::trainee)).result_int(), 403);

  // The attempt failed; the instructor passes it with a reason, which is audited and counts.
  const auto task_passes = [&] {
    const auto progress = json_of(get("/api/progress", tess_token));
    for (const auto& task : progress["tasks"])
      if (task["key"] == "palpation") return task["passed_attempts"].get<int>();
    return -1;
  };
  EXPECT_EQ(task_passes(), 0);
  EXPECT_TRUE(
      is_error(post(base + "/adjustments", {{"passed", true}, {"reason", "ok"}}, instructor),
               http::status::unprocessable_entity, "reason must be 3-500 characters"));
  EXPECT_TRUE(is_error(
      post(base + "/adjustments", {{"passed", "yes"}, {"reason", "the scale"}}, instructor),
      http::status::unprocessable_entity, "field 'passed' must be true or false"));
  EXPECT_EQ(
      post(base + "/adjustments", {{"passed", true}, {"reason", "a sensor spike"}}, tess_token)
          .result_int(),
      403);
  const auto adjusted =
      post(base + "/adjustments", {{"passed", true}, {"reason", "a sensor spike, not the trainee"}},
           instructor);
  ASSERT_EQ(adjusted.result_int(), 201) << adjusted.body();
  EXPECT_EQ(task_passes(), 1);
  const auto history = json_of(get(base + "/adjustments", tess_token));
  ASSERT_EQ(history.size(), 1u);
  EXPECT_EQ(history[0]["reason"], "a sensor spike, not the trainee");
  EXPECT_EQ(count("audit_log WHERE action = 'score.adjust'"), 1);

  // Only a finished attempt is adjusted.
  const auto running = training.create_session(tess, std::nullopt, "palpation", now());
  training.set_session_state(running, "running", now());
  EXPECT_EQ(post("/api/sessions/" + std::to_string(running) + "/adjustments",
                 {{"passed", true}, {"reason", "early"}}, instructor)
                .result_int(),
            409);

  // Nobody but an admin adjusts their own attempt.
  const auto own = training.create_session(user_id("instructor"), std::nullopt, "palpation", now());
  training.set_session_state(own, "finished", now() + 60);
  const auto own_path = "/api/sessions/" + std::to_string(own) + "/adjustments";
  EXPECT_TRUE(is_error(post(own_path, {{"passed", true}, {"reason", "felt good"}}, instructor),
                       http::status::forbidden, "you cannot adjust the score of your own attempt"));
  EXPECT_EQ(
      post(own_path, {{"passed", true}, {"reason", "an admin decides"}}, session_of(Who::admin))
          .result_int(),
      201);
}

}  // namespace
}  // namespace incise::server::test
