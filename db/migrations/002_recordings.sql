-- Recordings that can be replayed: what was simulated (scene id, a hash of the scene text, the
-- random seed, the tick rate) and whether the recorder is still appending. Rows from 001 had no
-- recorder behind them, so they default to 'complete' with an unknown scene.
ALTER TABLE recordings ADD COLUMN scene         TEXT    NOT NULL DEFAULT '';
ALTER TABLE recordings ADD COLUMN scene_version TEXT    NOT NULL DEFAULT '';
ALTER TABLE recordings ADD COLUMN seed          INTEGER NOT NULL DEFAULT 0;
ALTER TABLE recordings ADD COLUMN tick_hz       REAL    NOT NULL DEFAULT 0;
ALTER TABLE recordings ADD COLUMN state         TEXT    NOT NULL DEFAULT 'complete'
  CHECK (state IN ('recording', 'complete'));
-- A hash of the simulation state at the end of the run; a replay must end in the same one.
ALTER TABLE recordings ADD COLUMN final_state_hash TEXT NOT NULL DEFAULT '';

-- At start-up the server looks for recordings a crash left open; there are few, so index only them.
CREATE INDEX recordings_open ON recordings (id) WHERE state = 'recording';
