-- Instructor review of attempts: time-stamped annotations on a recorded session, and score
-- adjustments (an instructor's pass or fail for the attempt, with a reason; the latest counts).
CREATE TABLE annotations (
  id         INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  author_id  INTEGER NOT NULL REFERENCES users (id),
  t_s        REAL    NOT NULL CHECK (t_s >= 0),
  text       TEXT    NOT NULL,
  created_at INTEGER NOT NULL
);
CREATE INDEX annotations_session ON annotations (session_id, t_s);

CREATE TABLE score_adjustments (
  id         INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  author_id  INTEGER NOT NULL REFERENCES users (id),
  passed     INTEGER NOT NULL CHECK (passed IN (0, 1)),
  reason     TEXT    NOT NULL,
  created_at INTEGER NOT NULL
);
CREATE INDEX score_adjustments_session ON score_adjustments (session_id, id);
