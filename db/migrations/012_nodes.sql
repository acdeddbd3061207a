-- Server nodes sharing this database (docs/storage.md, "Nodes"): each one beats every few seconds,
-- and a live session belongs to the node that runs it (NULL: a session from before nodes).
CREATE TABLE nodes (
  id           TEXT    PRIMARY KEY,
  address      TEXT    NOT NULL DEFAULT '',
  started_at   INTEGER NOT NULL,
  heartbeat_at INTEGER NOT NULL
);
ALTER TABLE sessions ADD COLUMN node_id TEXT;
