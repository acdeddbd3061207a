-- PostgreSQL twin of db/migrations/011_user_state_retire_audit_diff.sql (same version, same meaning): BIGINT for INTEGER, DOUBLE
-- PRECISION for REAL, BYTEA for BLOB, identity ids, and text in SQLite's binary order ("C").
-- A disabled user cannot log in (their login sessions end when they are disabled); NULL = active.
ALTER TABLE users ADD COLUMN disabled_at BIGINT;
-- 1 after an admin reset the password: the user must choose a new one before anything else.
ALTER TABLE users ADD COLUMN must_change_password BIGINT NOT NULL DEFAULT 0
  CHECK (must_change_password IN (0, 1));

-- A retired station is kept for its history (sessions, recordings) but is no longer booked,
-- started or connected to; NULL = in service.
ALTER TABLE stations ADD COLUMN retired_at BIGINT;

-- What an audited change changed: the changed fields before and after, as JSON objects (never a
-- secret). NULL where there is no before (a creation) or no after (a removal).
ALTER TABLE audit_log ADD COLUMN before_json TEXT COLLATE "C";
ALTER TABLE audit_log ADD COLUMN after_json TEXT COLLATE "C";
