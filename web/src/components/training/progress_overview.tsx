import type { TaskProgress, TraineeProgress } from '../../api';

/** One task's standing in a cell: mastered, the current run of passes, or locked. */
function TaskCell({ task }: { task: TaskProgress }) {
  if (task.mastered) {
    return (
      <span className="badge badge-pass" title={`${task.attempts} attempts`}>
        Mastered
      </span>
    );
  }
  if (!task.unlocked) return <span className="muted">Locked</span>;
  if (task.attempts === 0) return <span className="muted">Not started</span>;
  return (
    <span title={`${task.passed_attempts} of ${task.attempts} attempts passed`}>
      {task.consecutive_passes}/{task.required_passes} in a row · {task.attempts} tries
    </span>
  );
}

/**
 * Instructors' view of every trainee at a glance: a row per trainee, a column per task of the
 * curriculum, each cell how far the trainee is with it.
 */
export function ProgressOverview({ trainees }: { trainees: TraineeProgress[] }) {
  const tasks = trainees[0]?.tasks ?? [];
  return (
    <div className="table-wrap">
      <table aria-labelledby="overview-title" data-testid="progress-overview">
        <thead>
          <tr>
            <th scope="col">Trainee</th>
            {tasks.map((t) => (
              <th key={t.key} scope="col">
                {t.name}
              </th>
            ))}
            <th scope="col">Mastered</th>
          </tr>
        </thead>
        <tbody>
          {trainees.map((trainee) => (
            <tr key={trainee.trainee_id}>
              <th scope="row">
                {trainee.display_name} <span className="muted">({trainee.username})</span>
              </th>
              {trainee.tasks.map((t) => (
                <td key={t.key}>
                  <TaskCell task={t} />
                </td>
              ))}
              <td className="numeric">
                {trainee.tasks.filter((t) => t.mastered).length}/{trainee.tasks.length}
              </td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
