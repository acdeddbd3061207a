-- Which node holds each station's agent link (docs/scale_out.md): a session of the station is
-- started there, and the other nodes forward a start to it. One row per connected station; the
-- node deletes it when the link goes, and the heartbeat sweep deletes a dead node's rows.
CREATE TABLE station_links (
  station_id INTEGER PRIMARY KEY REFERENCES stations(id),
  node_id    TEXT    NOT NULL,
  linked_at  INTEGER NOT NULL
);
