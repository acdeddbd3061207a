-- PostgreSQL twin of db/migrations/005_expert_runs.sql (same version, same meaning): BIGINT for INTEGER, DOUBLE
-- PRECISION for REAL, BYTEA for BLOB, identity ids, and text in SQLite's binary order ("C").
-- Expert benchmarks: attempts an admin marked as expert runs. A task's benchmark
-- is the mean and SD of each metric over its expert runs' scores, computed when asked.
CREATE TABLE expert_runs (
  session_id BIGINT PRIMARY KEY REFERENCES sessions (id) ON DELETE CASCADE,
  marked_by  BIGINT NOT NULL REFERENCES users (id),
  marked_at  BIGINT NOT NULL
);
