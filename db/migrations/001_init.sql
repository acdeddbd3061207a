-- Initial schema. Times are integer Unix seconds (UTC); the API formats them as ISO 8601.
CREATE TABLE users (
  id            INTEGER PRIMARY KEY,
  username      TEXT    NOT NULL UNIQUE,
  display_name  TEXT    NOT NULL,
  role          TEXT    NOT NULL CHECK (role IN ('trainee', 'instructor', 'admin')),
  password_hash TEXT    NOT NULL,
  created_at    INTEGER NOT NULL
);

-- Login sessions: only a hash of the cookie token is stored, so a database leak reveals no cookie.
CREATE TABLE auth_sessions (
  token_hash BLOB    PRIMARY KEY,
  user_id    INTEGER NOT NULL REFERENCES users (id) ON DELETE CASCADE,
  created_at INTEGER NOT NULL,
  expires_at INTEGER NOT NULL
);
CREATE INDEX auth_sessions_user ON auth_sessions (user_id);

CREATE TABLE stations (
  id         INTEGER PRIMARY KEY,
  name       TEXT    NOT NULL UNIQUE,
  location   TEXT    NOT NULL DEFAULT '',
  token_hash BLOB    NOT NULL UNIQUE,
  created_at INTEGER NOT NULL
);

CREATE TABLE bookings (
  id           INTEGER PRIMARY KEY,
  station_id   INTEGER NOT NULL REFERENCES stations (id),
  user_id      INTEGER NOT NULL REFERENCES users (id),
  starts_at    INTEGER NOT NULL,
  ends_at      INTEGER NOT NULL,
  status       TEXT    NOT NULL DEFAULT 'active' CHECK (status IN ('active', 'cancelled')),
  created_at   INTEGER NOT NULL,
  cancelled_at INTEGER,
  CHECK (ends_at > starts_at)
);
CREATE INDEX bookings_station_time ON bookings (station_id, starts_at);
CREATE INDEX bookings_user_time ON bookings (user_id, starts_at);

CREATE TABLE curricula (
  id         INTEGER PRIMARY KEY,
  name       TEXT    NOT NULL UNIQUE,
  definition TEXT    NOT NULL,  -- JSON, validated by curriculum/ before it is stored
  created_at INTEGER NOT NULL
);

CREATE TABLE sessions (
  id         INTEGER PRIMARY KEY,
  trainee_id INTEGER NOT NULL REFERENCES users (id),
  station_id INTEGER REFERENCES stations (id),
  booking_id INTEGER REFERENCES bookings (id),
  task       TEXT    NOT NULL,
  state      TEXT    NOT NULL CHECK (state IN ('created', 'running', 'paused', 'finished', 'aborted')),
  started_at INTEGER,
  ended_at   INTEGER,
  created_at INTEGER NOT NULL
);
CREATE INDEX sessions_trainee ON sessions (trainee_id);

CREATE TABLE recordings (
  id         INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL UNIQUE REFERENCES sessions (id) ON DELETE CASCADE,
  duration_s REAL    NOT NULL DEFAULT 0,
  created_at INTEGER NOT NULL
);

-- The recorded input log, appended in small chunks so that a crash loses at most the last one.
CREATE TABLE recording_chunks (
  recording_id INTEGER NOT NULL REFERENCES recordings (id) ON DELETE CASCADE,
  seq          INTEGER NOT NULL,
  t0_us        INTEGER NOT NULL,
  data         BLOB    NOT NULL,
  PRIMARY KEY (recording_id, seq)
);

CREATE TABLE scores (
  id         INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  metric     TEXT    NOT NULL,
  value      REAL    NOT NULL,
  unit       TEXT    NOT NULL DEFAULT '',
  passed     INTEGER NOT NULL CHECK (passed IN (0, 1)),
  created_at INTEGER NOT NULL,
  UNIQUE (session_id, metric)
);

CREATE TABLE audit_log (
  id      INTEGER PRIMARY KEY,
  at      INTEGER NOT NULL,
  user_id INTEGER REFERENCES users (id),
  action  TEXT    NOT NULL,
  detail  TEXT    NOT NULL DEFAULT ''
);
