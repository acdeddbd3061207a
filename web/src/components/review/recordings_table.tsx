import type { Recording } from '../../api';
import { Link } from '../../router';
import { format_date_time } from '../../time';
import { DataTable } from '../common/data_table';

export function RecordingsTable({ recordings, show_trainee }: { recordings: Recording[]; show_trainee: boolean }) {
  return (
    <DataTable<Recording>
      rows={recordings}
      row_key={(r) => r.id}
      columns={[
        { header: 'Session', cell: (r) => `#${r.session_id}` },
        show_trainee && { header: 'Trainee', cell: (r) => r.trainee },
        { header: 'Task', cell: (r) => r.task },
        { header: 'Duration', className: 'numeric', cell: (r) => `${r.duration_s.toFixed(1)} s` },
        { header: 'Recorded', cell: (r) => format_date_time(r.created_at) },
        {
          header: <span className="visually-hidden">Actions</span>,
          className: 'actions',
          cell: (r) => (
            <Link to={`/recordings/${r.id}`} label={`Replay the recording of session ${r.session_id}`}>
              Replay
            </Link>
          ),
        },
      ]}
    />
  );
}
