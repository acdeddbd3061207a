-- Which instructors teach which trainees (access control: instructors see only their trainees'
-- data). A trainee may have several instructors.
CREATE TABLE trainee_instructors (
  trainee_id    INTEGER NOT NULL REFERENCES users (id) ON DELETE CASCADE,
  instructor_id INTEGER NOT NULL REFERENCES users (id) ON DELETE CASCADE,
  assigned_at   INTEGER NOT NULL,
  PRIMARY KEY (trainee_id, instructor_id)
);
CREATE INDEX trainee_instructors_instructor ON trainee_instructors (instructor_id);

-- Before this migration every instructor saw every trainee: existing pairs keep that.
INSERT INTO trainee_instructors (trainee_id, instructor_id, assigned_at)
SELECT t.id, i.id, CAST(strftime('%s', 'now') AS INTEGER)
FROM users t, users i WHERE t.role = 'trainee' AND i.role = 'instructor';
