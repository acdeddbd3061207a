-- PostgreSQL twin of db/migrations/006_trainee_instructors.sql (same version, same meaning): BIGINT for INTEGER, DOUBLE
-- PRECISION for REAL, BYTEA for BLOB, identity ids, and text in SQLite's binary order ("C").
-- Which instructors teach which trainees (access control: instructors see only their trainees'
-- data). A trainee may have several instructors.
CREATE TABLE trainee_instructors (
  trainee_id    BIGINT NOT NULL REFERENCES users (id) ON DELETE CASCADE,
  instructor_id BIGINT NOT NULL REFERENCES users (id) ON DELETE CASCADE,
  assigned_at   BIGINT NOT NULL,
  PRIMARY KEY (trainee_id, instructor_id)
);
CREATE INDEX trainee_instructors_instructor ON trainee_instructors (instructor_id);

-- Before this migration every instructor saw every trainee: existing pairs keep that.
INSERT INTO trainee_instructors (trainee_id, instructor_id, assigned_at)
SELECT t.id, i.id, CAST(EXTRACT(EPOCH FROM now()) AS BIGINT)
FROM users t, users i WHERE t.role = 'trainee' AND i.role = 'instructor';
