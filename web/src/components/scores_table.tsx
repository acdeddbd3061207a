import type { Score } from '../api';
import { format_date_time } from '../time';
import { DataTable } from './data_table';
import { format_value } from './format';

export function ScoresTable({ scores, show_trainee }: { scores: Score[]; show_trainee: boolean }) {
  return (
    <DataTable<Score>
      rows={scores}
      row_key={(s) => s.id}
      columns={[
        { header: 'Session', cell: (s) => `#${s.session_id}` },
        show_trainee && { header: 'Trainee', cell: (s) => s.trainee },
        { header: 'Task', cell: (s) => s.task },
        { header: 'Metric', cell: (s) => s.metric },
        { header: 'Value', className: 'numeric', cell: (s) => format_value(s.value, s.unit) },
        {
          header: 'Result',
          cell: (s) => (
            <span className={`badge ${s.passed ? 'badge-pass' : 'badge-fail'}`}>{s.passed ? 'Passed' : 'Not passed'}</span>
          ),
        },
        { header: 'Recorded', cell: (s) => format_date_time(s.created_at) },
      ]}
    />
  );
}
