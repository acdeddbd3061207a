-- Tissue calibration (docs/calibration.md): jobs that fit a scene's material constants to an
-- uploaded probe data file, run in the background on the node that took them, and the named
-- materials saved from them, which a task names ("material") to run its scene with. A recording
-- keeps the name of the material its session ran with, for the replay; materials never change.
CREATE TABLE calibration_jobs (
  id               INTEGER PRIMARY KEY,
  scene            TEXT    NOT NULL,
  method           TEXT    NOT NULL CHECK (method IN ('ga', 'cmaes', 'lm')),
  per              TEXT    NOT NULL CHECK (per IN ('label', 'node')),
  budget           INTEGER NOT NULL CHECK (budget >= 1),
  data_name        TEXT    NOT NULL,
  data             TEXT    NOT NULL,
  contacts         INTEGER NOT NULL,
  samples          INTEGER NOT NULL,
  status           TEXT    NOT NULL
                   CHECK (status IN ('queued', 'running', 'done', 'failed', 'cancelled')),
  cancel_requested INTEGER NOT NULL DEFAULT 0 CHECK (cancel_requested IN (0, 1)),
  progress         TEXT,
  result           TEXT,
  error            TEXT,
  node_id          TEXT,
  created_by       INTEGER NOT NULL REFERENCES users (id),
  created_at       INTEGER NOT NULL,
  finished_at      INTEGER
);
CREATE INDEX calibration_jobs_status ON calibration_jobs (node_id, status);

CREATE TABLE materials (
  id         INTEGER PRIMARY KEY,
  name       TEXT    NOT NULL UNIQUE,
  scene      TEXT    NOT NULL,
  model      TEXT    NOT NULL,
  constants  TEXT    NOT NULL,
  job_id     INTEGER REFERENCES calibration_jobs (id),
  method     TEXT    NOT NULL,
  misfit     REAL    NOT NULL,
  created_by INTEGER NOT NULL REFERENCES users (id),
  created_at INTEGER NOT NULL
);

ALTER TABLE recordings ADD COLUMN material TEXT;
