-- Signals the simulation measured during a live session that its recording does not hold (the
-- tissue damage index of the simulation), sampled every interval_s from the session's start.
-- data: little-endian float64 values, one per sample.
CREATE TABLE session_signals (
  session_id INTEGER NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  name       TEXT    NOT NULL,
  interval_s REAL    NOT NULL CHECK (interval_s > 0),
  data       BLOB    NOT NULL,
  PRIMARY KEY (session_id, name)
);
