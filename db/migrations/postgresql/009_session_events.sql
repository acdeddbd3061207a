-- PostgreSQL twin of db/migrations/009_session_events.sql (same version, same meaning): BIGINT for INTEGER, DOUBLE
-- PRECISION for REAL, BYTEA for BLOB, identity ids, and text in SQLite's binary order ("C").
-- Events the simulation saw during a live session that its recording does not show: what a
-- surgical scene's tools did to the tissue (grasp, release, cut, a collision with a protected
-- structure, a never event). The review shows them as markers beside the events it finds in the
-- recording. t_s: seconds of simulated time from the session's start; hand: the device whose
-- tool it was (0 right, 1 left), -1 for none.
CREATE TABLE session_events (
  session_id BIGINT NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  seq        BIGINT NOT NULL CHECK (seq >= 0),
  t_s        DOUBLE PRECISION    NOT NULL CHECK (t_s >= 0),
  kind       TEXT COLLATE "C"    NOT NULL CHECK (kind IN ('grasp', 'release', 'cut', 'collision', 'never_event')),
  hand       BIGINT NOT NULL CHECK (hand BETWEEN -1 AND 1),
  label      TEXT COLLATE "C"    NOT NULL,
  PRIMARY KEY (session_id, seq)
);
