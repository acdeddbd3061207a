// Tests for db/session_events_repo.h: the simulation's events of a session, stored whole (all or
// none) and read back in order.
#include "db/session_events_repo.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <vector>

#include "db/db_error.h"
#include "db/training_repo.h"
#include "temp_database.h"

namespace incise::db {
namespace {

using test::row_count;

class SessionEventsRepoTest : public test::DbTest {
 protected:
  std::int64_t ann_ = test::add_user(db(), "ann");
  std::int64_t session_ = TrainingRepo(db()).create_session(ann_, std::nullopt, "liver_cut", 100);
  SessionEventsRepo events_{db()};
};

const std::vector<SessionEvent> kStroke = {
    {1.25, "grasp", 1, "3 vertices"},
    {3.5, "cut", 0, "cut 42.0 mm^2, 0.0 mm^2 off the marked line"},
    {3.5, "never_event", 0, "a protected tissue was cut"},
    {7.0, "release", 1, "opened, 3 vertices"},
    {8.0, "collision", -1, "femur"},
};

TEST_F(SessionEventsRepoTest, StoredEventsReadBackInOrder) {
  EXPECT_TRUE(events_.list(session_).empty());
  events_.set(session_, kStroke);
  EXPECT_EQ(events_.list(session_), kStroke);
  // Another session's are its own.
  const auto other = TrainingRepo(db()).create_session(ann_, std::nullopt, "liver_cut", 200);
  EXPECT_TRUE(events_.list(other).empty());
}

TEST_F(SessionEventsRepoTest, SettingAgainReplacesTheSessionsEvents) {
  events_.set(session_, kStroke);
  const std::vector<SessionEvent> fewer = {{2.0, "cut", 0, "again"}};
  events_.set(session_, fewer);
  EXPECT_EQ(events_.list(session_), fewer);
  events_.set(session_, {});
  EXPECT_TRUE(events_.list(session_).empty());
}

TEST_F(SessionEventsRepoTest, BadEventsAreRefusedAndNothingIsStored) {
  events_.set(session_, kStroke);
  const auto refused = [&](SessionEvent bad) {
    std::vector<SessionEvent> events = kStroke;
    events.push_back(std::move(bad));
    return events;
  };
  EXPECT_THROW(events_.set(session_, refused({1.0, "explosion", 0, ""})), ConstraintError);
  EXPECT_THROW(events_.set(session_, refused({1.0, "cut", 2, ""})), ConstraintError);
  EXPECT_THROW(events_.set(session_, refused({-0.5, "cut", 0, ""})), std::invalid_argument);
  EXPECT_THROW(
      events_.set(session_, refused({std::numeric_limits<double>::quiet_NaN(), "cut", 0, ""})),
      std::invalid_argument);
  EXPECT_THROW(events_.set(session_ + 100, kStroke), NotFound);
  // Each refusal left the stored events as they were.
  EXPECT_EQ(events_.list(session_), kStroke);
  EXPECT_EQ(row_count(db(), "session_events"), static_cast<std::int64_t>(kStroke.size()));
}

}  // namespace
}  // namespace incise::db
