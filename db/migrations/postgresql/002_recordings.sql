-- PostgreSQL twin of db/migrations/002_recordings.sql (same version, same meaning): BIGINT for INTEGER, DOUBLE
-- PRECISION for REAL, BYTEA for BLOB, identity ids, and text in SQLite's binary order ("C").
-- Recordings that can be replayed: what was simulated (scene id, a hash of the scene text, the
-- random seed, the tick rate) and whether the recorder is still appending. Rows from 001 had no
-- recorder behind them, so they default to 'complete' with an unknown scene.
ALTER TABLE recordings ADD COLUMN scene         TEXT COLLATE "C"    NOT NULL DEFAULT '';
ALTER TABLE recordings ADD COLUMN scene_version TEXT COLLATE "C"    NOT NULL DEFAULT '';
ALTER TABLE recordings ADD COLUMN seed          BIGINT NOT NULL DEFAULT 0;
ALTER TABLE recordings ADD COLUMN tick_hz       DOUBLE PRECISION    NOT NULL DEFAULT 0;
ALTER TABLE recordings ADD COLUMN state         TEXT COLLATE "C"    NOT NULL DEFAULT 'complete'
  CHECK (state IN ('recording', 'complete'));
-- A hash of the simulation state at the end of the run; a replay must end in the same one.
ALTER TABLE recordings ADD COLUMN final_state_hash TEXT COLLATE "C" NOT NULL DEFAULT '';

-- At start-up the server looks for recordings a crash left open; there are few, so index only them.
CREATE INDEX recordings_open ON recordings (id) WHERE state = 'recording';
