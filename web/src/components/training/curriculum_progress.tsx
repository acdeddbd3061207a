import type { Progress, TaskProgress } from '../../api';
import { DataTable } from '../common/data_table';

function status(task: TaskProgress): string {
  if (task.mastered) return 'Mastered';
  if (!task.unlocked) return 'Locked';
  return task.attempts === 0 ? 'Unlocked' : 'In progress';
}

/**
 * The trainee's curriculum: each task with where they stand. A task is mastered after its number
 * of passes in a row (every metric within its threshold), and unlocked once its prerequisites are
 * mastered.
 */
export function CurriculumProgress({ progress }: { progress: Progress }) {
  const names = new Map(progress.tasks.map((t) => [t.key, t.name]));
  return (
    <DataTable
      labelled_by="curriculum-title"
      rows={progress.tasks}
      row_key={(t) => t.key}
      row_class={(t) => (t.unlocked ? undefined : 'muted')}
      columns={[
        { header: 'Task', cell: (t) => t.name },
        { header: 'Module', cell: (t) => t.module },
        { header: 'Status', cell: (t) => <span data-testid={`task-status-${t.key}`}>{status(t)}</span> },
        {
          header: 'Passes in a row',
          className: 'numeric',
          cell: (t) => <span data-testid={`task-passes-${t.key}`}>{`${t.consecutive_passes} of ${t.required_passes}`}</span>,
        },
        { header: 'Attempts', className: 'numeric', cell: (t) => `${t.passed_attempts} passed of ${t.attempts}` },
        {
          header: 'Needs',
          cell: (t) => (t.prerequisites.length === 0 ? '—' : t.prerequisites.map((k) => names.get(k) ?? k).join(', ')),
        },
      ]}
    />
  );
}
