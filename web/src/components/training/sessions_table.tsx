import type { Session } from '../../api';
import { Link } from '../../router';
import { format_date_time } from '../../time';
import { DataTable } from '../common/data_table';

const state_labels: Record<Session['state'], string> = {
  created: 'Created',
  running: 'Running',
  paused: 'Paused',
  finished: 'Finished',
  aborted: 'Aborted',
};

export function SessionsTable({ sessions, show_trainee }: { sessions: Session[]; show_trainee: boolean }) {
  return (
    <DataTable<Session>
      rows={sessions}
      row_key={(s) => s.id}
      columns={[
        {
          header: 'Session',
          // The session page streams a live session and shows a finished one's result.
          cell: (s) => (
            <Link to={`/sessions/${s.id}`} label={`Session ${s.id}`}>
              #{s.id}
            </Link>
          ),
        },
        show_trainee && { header: 'Trainee', cell: (s) => s.trainee },
        { header: 'Task', cell: (s) => s.task },
        { header: 'Station', cell: (s) => s.station || '—' },
        {
          header: 'State',
          cell: (s) => <span className={`badge badge-${s.state}`}>{state_labels[s.state]}</span>,
        },
        { header: 'Started', cell: (s) => format_date_time(s.started_at) },
        { header: 'Ended', cell: (s) => format_date_time(s.ended_at) },
      ]}
    />
  );
}
