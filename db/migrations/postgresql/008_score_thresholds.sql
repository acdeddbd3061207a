-- PostgreSQL twin of db/migrations/008_score_thresholds.sql (same version, same meaning): BIGINT for INTEGER, DOUBLE
-- PRECISION for REAL, BYTEA for BLOB, identity ids, and text in SQLite's binary order ("C").
-- The threshold each score was judged against when it was stored, so that a review shows why an
-- attempt passed even after the curriculum's thresholds changed. NULL for scores stored before
-- (and for scores of a metric the task did not set a threshold for).
ALTER TABLE scores ADD COLUMN threshold_op TEXT COLLATE "C" CHECK (threshold_op IN ('<=', '>='));
ALTER TABLE scores ADD COLUMN threshold_value DOUBLE PRECISION;
