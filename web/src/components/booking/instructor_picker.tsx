import { useState } from 'react';
import { api, type ListedUser, type User } from '../../api';
import { error_text } from '../../use_resource';
import { ErrorAlert } from '../common/alerts';

/**
 * Which instructors teach one trainee: a checkbox per instructor. Each toggle saves the new set at
 * once; while it is under way every box is disabled so that two saves never race.
 */
export function InstructorPicker({
  trainee,
  instructors,
  on_saved,
}: {
  trainee: ListedUser;
  instructors: User[];
  on_saved: () => void;
}) {
  // The set being saved or just saved, kept only while the parent still holds the same
  // instructor_ids array: once it reloads the trainee, the server's answer is shown again.
  const [local, set_local] = useState<{ of: number[] | undefined; ids: number[] } | null>(null);
  const [busy, set_busy] = useState(false);
  const [error, set_error] = useState<string | null>(null);

  const server_ids = trainee.instructor_ids;
  const ids = local && local.of === server_ids ? local.ids : (server_ids ?? []);

  async function toggle(instructor_id: number, teaches: boolean) {
    const next = teaches ? [...ids, instructor_id] : ids.filter((id) => id !== instructor_id);
    set_local({ of: server_ids, ids: next });
    set_busy(true);
    set_error(null);
    try {
      // PUT replaces the whole set and answers the trainee with its new instructor_ids.
      const saved = await api.set_instructors(trainee.id, next);
      set_local({ of: server_ids, ids: saved.instructor_ids ?? next });
      on_saved();
    } catch (reason) {
      set_local(null);
      set_error(`Could not change the instructors of ${trainee.display_name}: ${error_text(reason)}`);
    } finally {
      set_busy(false);
    }
  }

  return (
    <div className="instructor-picker" data-testid={`instructor-picker-${trainee.id}`}>
      <fieldset aria-busy={busy}>
        <legend className="visually-hidden">
          {`Instructors of ${trainee.display_name}`}
        </legend>
        {instructors.length === 0 && <span className="empty">No instructors yet.</span>}
        {instructors.map((instructor) => {
          const id = `instructor-picker-${trainee.id}-${instructor.id}`;
          return (
            <span key={instructor.id} className="checkbox-option">
              <input
                id={id}
                type="checkbox"
                checked={ids.includes(instructor.id)}
                disabled={busy}
                onChange={(e) => void toggle(instructor.id, e.target.checked)}
              />
              <label htmlFor={id}>{instructor.display_name}</label>
            </span>
          );
        })}
      </fieldset>
      <ErrorAlert message={error} />
    </div>
  );
}
