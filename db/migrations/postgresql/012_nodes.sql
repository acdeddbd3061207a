-- PostgreSQL twin of db/migrations/012_nodes.sql (same version, same meaning): BIGINT for INTEGER,
-- and text in SQLite's binary order ("C").
CREATE TABLE nodes (
  id           TEXT COLLATE "C" PRIMARY KEY,
  address      TEXT COLLATE "C" NOT NULL DEFAULT '',
  started_at   BIGINT NOT NULL,
  heartbeat_at BIGINT NOT NULL
);
ALTER TABLE sessions ADD COLUMN node_id TEXT COLLATE "C";
