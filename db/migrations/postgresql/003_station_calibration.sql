-- PostgreSQL twin of db/migrations/003_station_calibration.sql (same version, same meaning): BIGINT for INTEGER, DOUBLE
-- PRECISION for REAL, BYTEA for BLOB, identity ids, and text in SQLite's binary order ("C").
-- A station's calibration (devices/kinematics.h StationCalibration as JSON): per device its kind
-- (pen or scope), workspace mapping (scale, rotation, offset) and, for a scope, the portal.
-- Empty = the default (two pens, identity mappings). The server sends it in the agent's welcome.
ALTER TABLE stations ADD COLUMN calibration TEXT COLLATE "C" NOT NULL DEFAULT '';
