// Tests for db/calibration_repo.h on the suite's engine: a node runs only its own queued jobs,
// oldest first; a cancel stops a queued job at once and flags a running one; a restart fails what
// the node left; materials keep unique names and the job they came from.
#include "db/calibration_repo.h"

#include <gtest/gtest.h>

#include "db/db_error.h"
#include "db/nodes_repo.h"
#include "db/recordings_repo.h"
#include "db/training_repo.h"
#include "temp_database.h"

namespace incise::db {
namespace {

class CalibrationRepoTest : public test::DbTest {
 protected:
  std::int64_t queue(const std::string& node, std::int64_t now) {
    NewCalibrationJob job;
    job.scene = "scenes/calibration/cube.json";
    job.method = "lm";
    job.per = "label";
    job.budget = 100;
    job.data_name = "cube.csv";
    job.data = "time_s,contact\n";
    job.contacts = 5;
    job.samples = 1005;
    job.node_id = node;
    job.created_by = ann_;
    return jobs_.create(job, now);
  }

  std::int64_t ann_ = test::add_user(db(), "ann");
  CalibrationJobsRepo jobs_{db()};
  MaterialsRepo materials_{db()};
};

TEST_F(CalibrationRepoTest, ANodeRunsItsOwnQueuedJobsOldestFirst) {
  const auto first = queue("a", 10);
  const auto elsewhere = queue("b", 11);
  const auto second = queue("a", 12);
  const auto job = jobs_.start_next("a");
  ASSERT_TRUE(job);
  EXPECT_EQ(job->id, first);
  EXPECT_EQ(job->status, "running");
  EXPECT_EQ(job->created_by_name, "ann");
  EXPECT_EQ(jobs_.start_next("a")->id, second);
  EXPECT_FALSE(jobs_.start_next("a"));
  EXPECT_EQ(jobs_.find(elsewhere)->status, "queued");
  EXPECT_EQ(jobs_.data(first), "time_s,contact\n");
  // Newest first.
  const auto all = jobs_.list();
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].id, second);
  EXPECT_EQ(all[2].id, first);
}

TEST_F(CalibrationRepoTest, ProgressCarriesACancelAndFinishStoresTheResult) {
  const auto id = queue("a", 10);
  jobs_.start_next("a");
  EXPECT_FALSE(jobs_.set_progress(id, R"({"iteration":1})"));
  EXPECT_TRUE(jobs_.request_cancel(id, 20));
  EXPECT_EQ(jobs_.find(id)->status, "running");  // running: flagged, the runner stops it
  EXPECT_TRUE(jobs_.set_progress(id, R"({"iteration":2})"));
  EXPECT_EQ(jobs_.find(id)->progress, R"({"iteration":2})");
  jobs_.finish(id, "cancelled", R"({"material":{}})", "cancelled", 30);
  const auto ended = jobs_.find(id);
  EXPECT_EQ(ended->status, "cancelled");
  EXPECT_EQ(ended->error, "cancelled");
  EXPECT_EQ(ended->finished_at, 30);
  EXPECT_EQ(jobs_.result(id), R"({"material":{}})");
  EXPECT_FALSE(jobs_.request_cancel(id, 40));  // ended
}

TEST_F(CalibrationRepoTest, AQueuedJobCancelsAtOnceAndARestartFailsWhatWasLeft) {
  const auto queued = queue("a", 10);
  EXPECT_TRUE(jobs_.request_cancel(queued, 15));
  EXPECT_EQ(jobs_.find(queued)->status, "cancelled");
  EXPECT_FALSE(jobs_.start_next("a"));

  const auto running = queue("a", 20);
  const auto waiting = queue("a", 21);
  const auto other = queue("b", 22);
  jobs_.start_next("a");
  EXPECT_EQ(jobs_.fail_unfinished("a", "the server stopped while it ran", 30), 2);
  for (const auto id : {running, waiting}) {
    EXPECT_EQ(jobs_.find(id)->status, "failed");
    EXPECT_EQ(jobs_.find(id)->error, "the server stopped while it ran");
  }
  EXPECT_EQ(jobs_.find(other)->status, "queued");
  EXPECT_EQ(jobs_.find(queued)->status, "cancelled");
}

// A node that stops beating leaves its jobs to nobody: the sweep fails them.
TEST_F(CalibrationRepoTest, TheSweepOfADeadNodeFailsItsJobs) {
  NodesRepo nodes(db());
  nodes.start("a", "", 100);
  nodes.start("b", "", 100);
  const auto running = queue("b", 101);
  const auto waiting = queue("b", 102);
  const auto mine = queue("a", 103);
  jobs_.start_next("b");
  nodes.heartbeat("a", "", 200);
  EndedSessions ended;
  EXPECT_EQ(nodes.sweep("a", 200, 30, ended), std::vector<std::string>{"b"});
  for (const auto id : {running, waiting}) {
    EXPECT_EQ(jobs_.find(id)->status, "failed");
    EXPECT_EQ(jobs_.find(id)->error, "its server node stopped");
    EXPECT_EQ(jobs_.find(id)->finished_at, 200);
  }
  EXPECT_EQ(jobs_.find(mine)->status, "queued");
}

TEST_F(CalibrationRepoTest, MaterialsHaveUniqueNamesAndNameTheirJob) {
  const auto job = queue("a", 10);
  Material m;
  m.name = "Calibrated cube";
  m.scene = "scenes/calibration/cube.json";
  m.model = "mss";
  m.constants = R"({"material":{"E":3600}})";
  m.job_id = job;
  m.method = "lm";
  m.misfit = 1e-9;
  m.created_by = ann_;
  const auto id = materials_.create(m, 50);
  const auto found = materials_.find_by_name("Calibrated cube");
  ASSERT_TRUE(found);
  EXPECT_EQ(found->id, id);
  EXPECT_EQ(found->constants, m.constants);
  EXPECT_EQ(found->job_id, job);
  EXPECT_DOUBLE_EQ(found->misfit, 1e-9);
  EXPECT_EQ(found->created_by_name, "ann");
  EXPECT_EQ(jobs_.find(job)->material, "Calibrated cube");
  EXPECT_THROW(materials_.create(m, 60), ConstraintError);
  EXPECT_FALSE(materials_.find_by_name("calibrated cube"));  // names are exact
  EXPECT_EQ(materials_.list().size(), 1u);
}

// A recording keeps the material its session ran with; without one it reads "".
TEST_F(CalibrationRepoTest, ARecordingKeepsItsMaterial) {
  TrainingRepo training(db());
  RecordingsRepo recordings(db());
  const auto with = training.create_session(ann_, std::nullopt, "palpation", 10, std::nullopt, "a");
  const auto without =
      training.create_session(ann_, std::nullopt, "palpation", 11, std::nullopt, "a");
  const auto r1 = recordings.create(with, "scenes/palpation.json", "6:abc", 0, 500, 12, "Cube");
  const auto r2 = recordings.create(without, "scenes/palpation.json", "6:abc", 0, 500, 13);
  EXPECT_EQ(recordings.find(r1)->material, "Cube");
  EXPECT_EQ(recordings.find(r2)->material, "");
}

}  // namespace
}  // namespace incise::db
