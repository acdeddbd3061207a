// Tests for db/bookings_repo.h: the overlap rules on half-open intervals [starts_at, ends_at),
// cancelling, listing, and that a refused create changes nothing. The random-sequence and
// two-thread tests are in bookings_repo_property_test.cpp.
#include "db/bookings_repo.h"

#include <gtest/gtest.h>

#include <exception>
#include <optional>
#include <type_traits>
#include <utility>

#include "db/statement.h"
#include "temp_database.h"

namespace incise::db {
namespace {

using test::row_count;

class BookingsRepoTest : public test::DbTest {
 protected:
  // Expects `create` to be refused with a BookingConflict and to change nothing.
  BookingConflict expect_conflict(std::int64_t station, std::int64_t user, std::int64_t t0,
                                  std::int64_t t1) {
    const auto rows = row_count(db(), "bookings");
    try {
      bookings_.create(station, user, t0, t1, 99);
    } catch (const BookingConflict& e) {
      EXPECT_EQ(row_count(db(), "bookings"), rows) << "a refused create changed the table";
      return e;
    }
    ADD_FAILURE() << "no conflict for [" << t0 << ", " << t1 << ")";
    return BookingConflict(Booking{}, false);
  }

  // A finished session of ann's at s1, held in #booking (none: without one).
  std::int64_t session_in(std::optional<std::int64_t> booking) {
    return db()
        .prepare(
            "INSERT INTO sessions (trainee_id, station_id, task, state, created_at, booking_id) "
            "VALUES (?, ?, 't', 'finished', 0, ?) RETURNING id")
        .bind(1, ann_)
        .bind(2, s1_)
        .bind(3, booking)
        .insert();
  }

  std::int64_t s1_ = test::add_station(db(), "s1");
  std::int64_t s2_ = test::add_station(db(), "s2");
  std::int64_t ann_ = test::add_user(db(), "ann");
  std::int64_t bob_ = test::add_user(db(), "bob");
  BookingsRepo bookings_{db()};
};

TEST(BookingConflict, IsAConflict) {
  EXPECT_TRUE((std::is_base_of_v<Conflict, BookingConflict>));
}

TEST_F(BookingsRepoTest, CreateReturnsTheStoredBooking) {
  const Booking b = bookings_.create(s1_, ann_, 100, 200, 50);
  EXPECT_GT(b.id, 0);
  EXPECT_EQ(b.station_id, s1_);
  EXPECT_EQ(b.station_name, "s1");
  EXPECT_EQ(b.user_id, ann_);
  EXPECT_EQ(b.username, "ann");
  EXPECT_EQ(b.starts_at, 100);
  EXPECT_EQ(b.ends_at, 200);
  EXPECT_EQ(b.status, "active");
  EXPECT_EQ(b.created_at, 50);
  const auto found = bookings_.find(b.id);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->id, b.id);
  EXPECT_EQ(found->starts_at, 100);
  EXPECT_EQ(found->ends_at, 200);
  EXPECT_FALSE(bookings_.find(b.id + 1));
}

TEST_F(BookingsRepoTest, AdjacentSlotsDoNotOverlap) {
  EXPECT_NO_THROW(bookings_.create(s1_, ann_, 10, 11, 0));
  EXPECT_NO_THROW(bookings_.create(s1_, ann_, 11, 12, 0));
  EXPECT_NO_THROW(bookings_.create(s1_, bob_, 9, 10, 0));
  EXPECT_EQ(row_count(db(), "bookings"), 3);
}

TEST_F(BookingsRepoTest, AnyOverlapAtTheSameStationConflicts) {
  const Booking held = bookings_.create(s1_, ann_, 10, 20, 0);
  const std::int64_t overlapping[][2] = {{5, 15},  {15, 25}, {12, 18}, {5, 25},
                                         {10, 20}, {19, 20}, {10, 11}, {0, 11}};
  for (const auto& slot : overlapping) {
    const auto e = expect_conflict(s1_, bob_, slot[0], slot[1]);
    EXPECT_TRUE(e.same_station()) << slot[0] << ", " << slot[1];
    EXPECT_EQ(e.existing().id, held.id);
    EXPECT_EQ(e.existing().station_id, s1_);
    EXPECT_EQ(e.existing().user_id, ann_);
    EXPECT_EQ(e.existing().starts_at, 10);
    EXPECT_EQ(e.existing().ends_at, 20);
    EXPECT_EQ(e.existing().status, "active");
  }
}

TEST_F(BookingsRepoTest, SamePersonAtAnotherStationConflicts) {
  const Booking held = bookings_.create(s1_, ann_, 10, 20, 0);
  const auto e = expect_conflict(s2_, ann_, 15, 25);
  EXPECT_FALSE(e.same_station());
  EXPECT_EQ(e.existing().id, held.id);
  EXPECT_EQ(e.existing().station_id, s1_);
  EXPECT_EQ(e.existing().username, "ann");
}

TEST_F(BookingsRepoTest, OtherPersonAtOtherStationDoesNotConflict) {
  bookings_.create(s1_, ann_, 10, 20, 0);
  EXPECT_NO_THROW(bookings_.create(s2_, bob_, 10, 20, 0));
}

TEST_F(BookingsRepoTest, CancelledBookingFreesItsSlot) {
  const Booking first = bookings_.create(s1_, ann_, 10, 20, 0);
  bookings_.cancel(first.id, 5);
  const auto cancelled = bookings_.find(first.id);
  ASSERT_TRUE(cancelled);
  EXPECT_EQ(cancelled->status, "cancelled");
  auto q = db().prepare("SELECT cancelled_at FROM bookings WHERE id = ?");
  q.bind(1, first.id);
  ASSERT_TRUE(q.step());
  EXPECT_EQ(q.optional_int64(0), 5);

  const Booking second = bookings_.create(s1_, bob_, 10, 20, 6);
  EXPECT_NE(second.id, first.id);
  EXPECT_NO_THROW(bookings_.create(s2_, ann_, 10, 20, 7)) << "ann's own time is free again";
}

TEST_F(BookingsRepoTest, CancellingTwiceThrowsConflict) {
  const Booking b = bookings_.create(s1_, ann_, 10, 20, 0);
  bookings_.cancel(b.id, 1);
  EXPECT_THROW(bookings_.cancel(b.id, 2), Conflict);
  auto q = db().prepare("SELECT cancelled_at FROM bookings WHERE id = ?");
  q.bind(1, b.id);
  ASSERT_TRUE(q.step());
  EXPECT_EQ(q.int64(0), 1) << "the second cancel changed the row";
}

TEST_F(BookingsRepoTest, CancellingAnUnknownBookingThrowsNotFound) {
  EXPECT_THROW(bookings_.cancel(12345, 1), NotFound);
}

TEST_F(BookingsRepoTest, UnknownStationOrUserThrowsNotFoundAndChangesNothing) {
  EXPECT_THROW(bookings_.create(s2_ + 100, ann_, 10, 20, 0), NotFound);
  EXPECT_THROW(bookings_.create(s1_, bob_ + 100, 10, 20, 0), NotFound);
  EXPECT_EQ(row_count(db(), "bookings"), 0);
}

// ends_at <= starts_at is refused by the schema's CHECK; the user exists, so reporting it as
// NotFound ("user does not exist") would send the client looking for the wrong problem.
TEST_F(BookingsRepoTest, EmptyOrInvertedIntervalIsRefusedButNotAsNotFound) {
  for (const auto& slot : {std::pair<std::int64_t, std::int64_t>{20, 20}, {30, 20}}) {
    try {
      bookings_.create(s1_, ann_, slot.first, slot.second, 0);
      ADD_FAILURE() << "accepted [" << slot.first << ", " << slot.second << ")";
    } catch (const NotFound& e) {
      ADD_FAILURE() << "reported as NotFound: " << e.what();
    } catch (const std::exception&) {
    }
  }
  EXPECT_EQ(row_count(db(), "bookings"), 0);
}

TEST_F(BookingsRepoTest, ListOfAUserReturnsOnlyTheirs) {
  const Booking a1 = bookings_.create(s1_, ann_, 10, 20, 0);
  const Booking b1 = bookings_.create(s2_, bob_, 10, 20, 0);
  const Booking a2 = bookings_.create(s2_, ann_, 30, 40, 0);
  const auto anns = bookings_.list(ann_);
  ASSERT_EQ(anns.size(), 2u);
  for (const auto& b : anns)
    EXPECT_EQ(b.user_id, ann_);
  EXPECT_EQ(anns[0].id, a2.id);
  EXPECT_EQ(anns[1].id, a1.id);
  const auto bobs = bookings_.list(bob_);
  ASSERT_EQ(bobs.size(), 1u);
  EXPECT_EQ(bobs[0].id, b1.id);
  EXPECT_TRUE(bookings_.list(bob_ + 100).empty());
}

TEST_F(BookingsRepoTest, ListIsNewestFirstAndIncludesCancelled) {
  const Booking early = bookings_.create(s1_, ann_, 10, 20, 0);
  const Booking late = bookings_.create(s1_, ann_, 50, 60, 0);
  const Booking middle = bookings_.create(s2_, bob_, 30, 40, 0);
  bookings_.cancel(middle.id, 1);
  const auto all = bookings_.list();
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].id, late.id);
  EXPECT_EQ(all[1].id, middle.id);
  EXPECT_EQ(all[1].status, "cancelled");
  EXPECT_EQ(all[2].id, early.id);
}

TEST_F(BookingsRepoTest, CoveringFindsThePersonsActiveBookingOfTheStationAtThatMoment) {
  const Booking b = bookings_.create(s1_, ann_, 100, 200, 50);
  bookings_.create(s2_, bob_, 100, 200, 50);
  EXPECT_EQ(bookings_.covering(ann_, s1_, 100)->id, b.id);  // the start is inside
  EXPECT_EQ(bookings_.covering(ann_, s1_, 199)->id, b.id);
  EXPECT_FALSE(bookings_.covering(ann_, s1_, 200));  // the end is not
  EXPECT_FALSE(bookings_.covering(ann_, s1_, 99));
  EXPECT_FALSE(bookings_.covering(ann_, s2_, 150));  // bob's
  EXPECT_FALSE(bookings_.covering(bob_, s1_, 150));
  bookings_.cancel(b.id, 120);
  EXPECT_FALSE(bookings_.covering(ann_, s1_, 150));
}

// Bookings follow sessions: the session's end completes its booking and frees the rest of the
// slot, so the person may book another station at once.
TEST_F(BookingsRepoTest, ASessionsEndCompletesItsBookingAndFreesTheRestOfTheSlot) {
  const Booking b = bookings_.create(s1_, ann_, 100, 200, 50);
  const auto session = session_in(b.id);
  // Without the completion, another station in the same slot is an overlap of the same person.
  EXPECT_FALSE(expect_conflict(s2_, ann_, 150, 200).same_station());

  EXPECT_TRUE(bookings_.complete_for_session(session, 140));
  const auto done = bookings_.find(b.id);
  EXPECT_EQ(done->status, "completed");
  EXPECT_EQ(done->starts_at, 100);
  EXPECT_EQ(done->ends_at, 140);
  EXPECT_FALSE(bookings_.covering(ann_, s1_, 150));
  // The rest of the slot is free, for her at another station and for bob at this one.
  EXPECT_NO_THROW(bookings_.create(s2_, ann_, 150, 200, 141));
  EXPECT_NO_THROW(bookings_.create(s1_, bob_, 140, 200, 141));
  // Also a walk-up slot that began before the end (the quarter hour in progress): that time is
  // spent.
  EXPECT_NO_THROW(bookings_.create(s1_, ann_, 100, 110, 142));
  // Completed once: a second end, or a cancel, changes nothing.
  EXPECT_FALSE(bookings_.complete_for_session(session, 160));
  EXPECT_EQ(bookings_.find(b.id)->ends_at, 140);
  EXPECT_THROW(bookings_.cancel(b.id, 170), Conflict);
  // A session without a booking completes none.
  EXPECT_FALSE(bookings_.complete_for_session(session_in(std::nullopt), 170));
}

TEST_F(BookingsRepoTest, AnEndAtTheStartOrAfterTheSlotKeepsTheBookingAnInterval) {
  const Booking early = bookings_.create(s1_, ann_, 100, 200, 50);
  const Booking late = bookings_.create(s1_, ann_, 300, 400, 50);
  EXPECT_TRUE(bookings_.complete_for_session(session_in(early.id), 100));
  EXPECT_EQ(bookings_.find(early.id)->ends_at, 101);  // still after its start
  EXPECT_TRUE(bookings_.complete_for_session(session_in(late.id), 450));
  EXPECT_EQ(bookings_.find(late.id)->ends_at, 400);  // never later than booked
  EXPECT_EQ(bookings_.find(late.id)->status, "completed");
}

}  // namespace
}  // namespace incise::db
