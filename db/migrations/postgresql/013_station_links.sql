-- PostgreSQL twin of db/migrations/013_station_links.sql (same version, same meaning).
CREATE TABLE station_links (
  station_id BIGINT PRIMARY KEY REFERENCES stations(id),
  node_id    TEXT COLLATE "C" NOT NULL,
  linked_at  BIGINT NOT NULL
);
