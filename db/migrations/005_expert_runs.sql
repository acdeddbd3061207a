-- Expert benchmarks: attempts an admin marked as expert runs. A task's benchmark
-- is the mean and SD of each metric over its expert runs' scores, computed when asked.
CREATE TABLE expert_runs (
  session_id INTEGER PRIMARY KEY REFERENCES sessions (id) ON DELETE CASCADE,
  marked_by  INTEGER NOT NULL REFERENCES users (id),
  marked_at  INTEGER NOT NULL
);
