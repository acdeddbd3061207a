// Tests for db/recordings_repo.h: a recording's metadata, its chunks appended strictly in order
// (each in its own transaction), finishing, and that a crash mid-recording keeps every committed
// chunk readable.
#include "db/recordings_repo.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "db/migrations.h"
#include "db/statement.h"
#include "temp_database.h"

namespace incise::db {
namespace {

using Bytes = std::vector<std::uint8_t>;
using test::row_count;

std::int64_t add_session(Database& db, std::int64_t trainee_id) {
  return db
      .prepare(
          "INSERT INTO sessions (trainee_id, task, state, created_at) VALUES (?, 'palpation', "
          "'running', 0) RETURNING id")
      .bind(1, trainee_id)
      .insert();
}

// Chunk contents that differ by seq and length, so that a swap or a truncation shows.
Bytes chunk_bytes(std::int64_t seq) {
  Bytes bytes(static_cast<std::size_t>(100 + 37 * seq));
  for (std::size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<std::uint8_t>((i * 31 + static_cast<std::size_t>(seq) * 7) & 0xff);
  return bytes;
}

// The recorder's chunk k starts k/10 s in and the recording then lasts (k + 1)/10 s.
std::int64_t t0_us(std::int64_t seq) {
  return seq * 100'000;
}
double duration_after(std::int64_t seq) {
  return 0.1 * static_cast<double>(seq + 1);
}

void expect_chunks(const std::vector<RecordingsRepo::Chunk>& chunks, std::int64_t count) {
  ASSERT_EQ(chunks.size(), static_cast<std::size_t>(count));
  for (std::int64_t k = 0; k < count; ++k) {
    const auto& c = chunks[static_cast<std::size_t>(k)];
    EXPECT_EQ(c.seq, k);
    EXPECT_EQ(c.t0_us, t0_us(k));
    EXPECT_EQ(c.data, chunk_bytes(k)) << "chunk " << k;
  }
}

class RecordingsRepoTest : public test::DbTest {
 protected:
  std::int64_t ann_ = test::add_user(db(), "ann");
  std::int64_t session_ = add_session(db(), ann_);
  RecordingsRepo recordings_{db()};

  std::int64_t open_recording(std::int64_t session) {
    return recordings_.create(session, "scenes/palpation.json", "sha256:ab12", 42, 500.0, 1000);
  }
  void append(std::int64_t recording, std::int64_t seq) {
    recordings_.append_chunk(recording, seq, t0_us(seq), chunk_bytes(seq), duration_after(seq));
  }
};

TEST_F(RecordingsRepoTest, CreateOpensARecordingWithItsMetadata) {
  const std::int64_t seed = -0x7123456789abcdefLL;  // a uint64 seed with its top bit set
  const auto id =
      recordings_.create(session_, "scenes/palpation.json", "sha256:ab12", seed, 500.0, 1000);
  const auto meta = recordings_.find(id);
  ASSERT_TRUE(meta.has_value());
  EXPECT_EQ(meta->id, id);
  EXPECT_EQ(meta->session_id, session_);
  EXPECT_EQ(meta->scene, "scenes/palpation.json");
  EXPECT_EQ(meta->scene_version, "sha256:ab12");
  EXPECT_EQ(meta->seed, seed);
  EXPECT_EQ(meta->tick_hz, 500.0);
  EXPECT_EQ(meta->duration_s, 0.0);
  EXPECT_EQ(meta->state, "recording");
  EXPECT_EQ(meta->created_at, 1000);

  const auto by_session = recordings_.find_by_session(session_);
  ASSERT_TRUE(by_session.has_value());
  EXPECT_EQ(by_session->id, id);
  EXPECT_EQ(by_session->seed, seed);
  EXPECT_TRUE(recordings_.chunks(id).empty());
}

TEST_F(RecordingsRepoTest, FindUnknownIsEmpty) {
  open_recording(session_);
  EXPECT_EQ(recordings_.find(4242), std::nullopt);
  EXPECT_EQ(recordings_.find_by_session(session_ + 100), std::nullopt);
  const auto other = add_session(db(), ann_);
  EXPECT_EQ(recordings_.find_by_session(other), std::nullopt) << "a session without recording";
  EXPECT_TRUE(recordings_.chunks(4242).empty());
}

TEST_F(RecordingsRepoTest, CreateRefusesBadTickRateUnknownSessionAndASecondRecording) {
  for (double bad : {0.0, -500.0, std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()}) {
    EXPECT_THROW(recordings_.create(session_, "s", "v", 1, bad, 0), std::invalid_argument) << bad;
  }
  EXPECT_THROW(recordings_.create(session_ + 100, "s", "v", 1, 500.0, 0), ConstraintError);
  open_recording(session_);
  EXPECT_THROW(open_recording(session_), ConstraintError) << "one recording per session";
  EXPECT_EQ(row_count(db(), "recordings"), 1);
}

TEST_F(RecordingsRepoTest, ChunksAreReadBackInSeqOrderAndMoveTheDuration) {
  const auto id = open_recording(session_);
  for (std::int64_t k = 0; k < 12; ++k) {
    append(id, k);
    EXPECT_DOUBLE_EQ(recordings_.find(id)->duration_s, duration_after(k));
  }
  expect_chunks(recordings_.chunks(id), 12);
  EXPECT_EQ(recordings_.find(id)->state, "recording");
}

TEST_F(RecordingsRepoTest, AnEmptyChunkRoundTripsAsEmpty) {
  const auto id = open_recording(session_);
  recordings_.append_chunk(id, 0, 0, Bytes{}, 0.0);
  const auto chunks = recordings_.chunks(id);
  ASSERT_EQ(chunks.size(), 1u);
  EXPECT_TRUE(chunks[0].data.empty());
}

TEST_F(RecordingsRepoTest, SeqMustBeTheNextOneElseNothingChanges) {
  const auto id = open_recording(session_);
  try {
    append(id, 1);
    FAIL() << "the first chunk must be seq 0";
  } catch (const ConstraintError& e) {
    EXPECT_NE(std::string(e.what()).find("expected 0"), std::string::npos) << e.what();
  }
  append(id, 0);
  append(id, 1);
  for (std::int64_t bad : {3, 1, 0, -1}) {
    try {
      recordings_.append_chunk(id, bad, t0_us(2), chunk_bytes(2), duration_after(2));
      FAIL() << "seq " << bad << " accepted after 1";
    } catch (const ConstraintError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("seq " + std::to_string(bad)), std::string::npos) << message;
      EXPECT_NE(message.find("expected 2"), std::string::npos) << message;
    }
  }
  expect_chunks(recordings_.chunks(id), 2);
  EXPECT_DOUBLE_EQ(recordings_.find(id)->duration_s, duration_after(1))
      << "a refused chunk must not move the duration";
  append(id, 2);
  expect_chunks(recordings_.chunks(id), 3);
}

TEST_F(RecordingsRepoTest, EachRecordingCountsItsOwnSeq) {
  const auto a = open_recording(session_);
  const auto b = open_recording(add_session(db(), ann_));
  append(a, 0);
  append(b, 0);
  append(a, 1);
  append(b, 1);
  append(b, 2);
  expect_chunks(recordings_.chunks(a), 2);
  expect_chunks(recordings_.chunks(b), 3);
}

TEST_F(RecordingsRepoTest, BadAppendsAreRefusedWithoutChange) {
  const auto id = open_recording(session_);
  append(id, 0);
  EXPECT_THROW(recordings_.append_chunk(4242, 0, 0, chunk_bytes(0), 1.0), NotFound);
  for (double bad :
       {-0.5, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    EXPECT_THROW(recordings_.append_chunk(id, 1, t0_us(1), chunk_bytes(1), bad),
                 std::invalid_argument);
  }
  EXPECT_THROW(recordings_.append_chunk(id, 1, -1, chunk_bytes(1), 0.2), std::invalid_argument);
  expect_chunks(recordings_.chunks(id), 1);
  EXPECT_DOUBLE_EQ(recordings_.find(id)->duration_s, duration_after(0));
}

TEST_F(RecordingsRepoTest, FinishCompletesAndClosesTheRecording) {
  const auto id = open_recording(session_);
  append(id, 0);
  append(id, 1);
  recordings_.finish(id, 0.25);
  const auto meta = recordings_.find(id);
  EXPECT_EQ(meta->state, "complete");
  EXPECT_DOUBLE_EQ(meta->duration_s, 0.25);
  EXPECT_THROW(append(id, 2), Conflict) << "no chunks after the end";
  EXPECT_THROW(recordings_.finish(id, 0.3), Conflict) << "finished twice";
  EXPECT_THROW(recordings_.finish(4242, 1.0), NotFound);
  EXPECT_THROW(recordings_.finish(open_recording(add_session(db(), ann_)), -1.0),
               std::invalid_argument);
  expect_chunks(recordings_.chunks(id), 2);
  EXPECT_DOUBLE_EQ(recordings_.find(id)->duration_s, 0.25);
}

TEST_F(RecordingsRepoTest, UnfinishedListsOpenRecordingsOldestFirst) {
  const auto a = open_recording(session_);
  const auto b = open_recording(add_session(db(), ann_));
  const auto c = open_recording(add_session(db(), ann_));
  recordings_.finish(b, 1.0);
  const auto open = recordings_.unfinished();
  ASSERT_EQ(open.size(), 2u);
  EXPECT_EQ(open[0].id, a);
  EXPECT_EQ(open[1].id, c);
  for (const auto& m : open)
    EXPECT_EQ(m.state, "recording");
}

// The recorder's connection goes away without finish(); the next connection (the restarted
// server) finds the recording open with every chunk, and can close it.
TEST(RecordingsCrash, ConnectionClosedMidRecordingKeepsEveryChunk) {
  test::TempDatabase tmp;
  std::int64_t id = 0;
  {
    auto recorder = tmp.open_another();
    const auto session = add_session(*recorder, test::add_user(*recorder, "ann"));
    RecordingsRepo repo(*recorder);
    id = repo.create(session, "scenes/palpation.json", "v1", 7, 500.0, 0);
    for (std::int64_t k = 0; k < 20; ++k)
      repo.append_chunk(id, k, t0_us(k), chunk_bytes(k), duration_after(k));
  }
  auto restarted = tmp.open_another();
  RecordingsRepo repo(*restarted);
  const auto open = repo.unfinished();
  ASSERT_EQ(open.size(), 1u);
  EXPECT_EQ(open[0].id, id);
  EXPECT_DOUBLE_EQ(open[0].duration_s, duration_after(19));
  expect_chunks(repo.chunks(id), 20);
  repo.finish(id, open[0].duration_s);
  EXPECT_TRUE(repo.unfinished().empty());
  expect_chunks(repo.chunks(id), 20);
}

// A real crash: a child process records, leaves one chunk half written in an open transaction,
// and dies with _exit (no destructors, no close, no WAL checkpoint). The parent then opens the
// file as a restarted server would: every committed chunk is there, the half-written one is not.
TEST(RecordingsCrash, ProcessKilledMidRecordingKeepsEveryCommittedChunk) {
  test::TempDir dir;
  const auto path = dir.path() / "incise.db";
  constexpr std::int64_t committed = 25;
  std::int64_t id = 0;
  {
    // Set up, then close: no connection to the file may cross the fork (SQLite forbids it).
    Database db(path);
    apply_migrations(db);
    const auto session = add_session(db, test::add_user(db, "ann"));
    id = RecordingsRepo(db).create(session, "scenes/palpation.json", "v1", 7, 500.0, 0);
  }
  std::fflush(nullptr);
  const pid_t child = fork();
  ASSERT_NE(child, -1);
  if (child == 0) {
    int status = 1;
    try {
      auto* db = new Database(path);  // deliberately never closed
      RecordingsRepo repo(*db);
      for (std::int64_t k = 0; k < committed; ++k)
        repo.append_chunk(id, k, t0_us(k), chunk_bytes(k), duration_after(k));
      db->exec("BEGIN IMMEDIATE");
      db->prepare(
            "INSERT INTO recording_chunks (recording_id, seq, t0_us, data) VALUES (?, ?, ?, ?)")
          .bind(1, id)
          .bind(2, committed)
          .bind(3, t0_us(committed))
          .bind_blob(4, chunk_bytes(committed))
          .run();
      status = 0;
    } catch (...) {
    }
    _exit(status);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the recorder failed";

  // The chunks were in the write-ahead log only: this checks recovery, not a clean shutdown.
  const auto wal = std::filesystem::path(path.string() + "-wal");
  ASSERT_TRUE(std::filesystem::exists(wal));
  EXPECT_GT(std::filesystem::file_size(wal), 0u);

  Database restarted(path);
  RecordingsRepo repo(restarted);
  const auto meta = repo.find(id);
  ASSERT_TRUE(meta.has_value());
  EXPECT_EQ(meta->state, "recording");
  EXPECT_DOUBLE_EQ(meta->duration_s, duration_after(committed - 1));
  expect_chunks(repo.chunks(id), committed);
  // The file is writable again (the dead process's locks are gone) and the recording can close.
  repo.finish(id, meta->duration_s);
  EXPECT_EQ(repo.find(id)->state, "complete");
  expect_chunks(repo.chunks(id), committed);
}

}  // namespace
}  // namespace incise::db
