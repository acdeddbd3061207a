-- PostgreSQL twin of db/migrations/010_completion_kinds_booking_end.sql (same version, same meaning): BIGINT for INTEGER, DOUBLE
-- PRECISION for REAL, BYTEA for BLOB, identity ids, and text in SQLite's binary order ("C").
-- A score that is a completion criterion of its task (curriculum Task::completion: the tools
-- touched the tissue, every target was reached, a cut lies on the marked line) rather than a
-- metric's threshold. The review shows criteria apart; both decide whether the attempt passed.
ALTER TABLE scores ADD COLUMN criterion BIGINT NOT NULL DEFAULT 0 CHECK (criterion IN (0, 1));

-- The kind of station (what its devices and scenes are: "bench", "laparoscopy", "arthroscopy"),
-- matched against a task's station_kind. '' = not declared: such a station runs only tasks that
-- name no kind.
ALTER TABLE stations ADD COLUMN kind TEXT COLLATE "C" NOT NULL DEFAULT '';

-- When the session held in the booking ended it (ends_at was then cut back to that moment, so
-- the rest of the slot is free); NULL while the booking is open or was cancelled.
ALTER TABLE bookings ADD COLUMN completed_at BIGINT;
