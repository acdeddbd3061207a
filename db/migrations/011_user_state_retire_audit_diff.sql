-- A disabled user cannot log in (their login sessions end when they are disabled); NULL = active.
ALTER TABLE users ADD COLUMN disabled_at INTEGER;
-- 1 after an admin reset the password: the user must choose a new one before anything else.
ALTER TABLE users ADD COLUMN must_change_password INTEGER NOT NULL DEFAULT 0
  CHECK (must_change_password IN (0, 1));

-- A retired station is kept for its history (sessions, recordings) but is no longer booked,
-- started or connected to; NULL = in service.
ALTER TABLE stations ADD COLUMN retired_at INTEGER;

-- What an audited change changed: the changed fields before and after, as JSON objects (never a
-- secret). NULL where there is no before (a creation) or no after (a removal).
ALTER TABLE audit_log ADD COLUMN before_json TEXT;
ALTER TABLE audit_log ADD COLUMN after_json TEXT;
