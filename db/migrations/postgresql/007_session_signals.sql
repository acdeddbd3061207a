-- PostgreSQL twin of db/migrations/007_session_signals.sql (same version, same meaning): BIGINT for INTEGER, DOUBLE
-- PRECISION for REAL, BYTEA for BLOB, identity ids, and text in SQLite's binary order ("C").
-- Signals the simulation measured during a live session that its recording does not hold (the
-- tissue damage index of the simulation), sampled every interval_s from the session's start.
-- data: little-endian float64 values, one per sample.
CREATE TABLE session_signals (
  session_id BIGINT NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  name       TEXT COLLATE "C"    NOT NULL,
  interval_s DOUBLE PRECISION    NOT NULL CHECK (interval_s > 0),
  data       BYTEA    NOT NULL,
  PRIMARY KEY (session_id, name)
);
