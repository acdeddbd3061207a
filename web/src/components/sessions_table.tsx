import type { Session } from '../api';
import { Link } from '../router';
import { format_date_time } from '../time';

const state_labels: Record<Session['state'], string> = {
  created: 'Created',
  running: 'Running',
  paused: 'Paused',
  finished: 'Finished',
  aborted: 'Aborted',
};

export function SessionsTable({ sessions, show_trainee }: { sessions: Session[]; show_trainee: boolean }) {
  return (
    <div className="table-wrap">
      <table>
        <thead>
          <tr>
            <th scope="col">Session</th>
            {show_trainee && <th scope="col">Trainee</th>}
            <th scope="col">Task</th>
            <th scope="col">Station</th>
            <th scope="col">State</th>
            <th scope="col">Started</th>
            <th scope="col">Ended</th>
          </tr>
        </thead>
        <tbody>
          {sessions.map((s) => (
            <tr key={s.id}>
              <td>
                {/* The session page streams a live session and shows a finished one's result. */}
                <Link to={`/sessions/${s.id}`} label={`Session ${s.id}`}>
                  #{s.id}
                </Link>
              </td>
              {show_trainee && <td>{s.trainee}</td>}
              <td>{s.task}</td>
              <td>{s.station || '—'}</td>
              <td>
                <span className={`badge badge-${s.state}`}>{state_labels[s.state] ?? s.state}</span>
              </td>
              <td>{format_date_time(s.started_at)}</td>
              <td>{format_date_time(s.ended_at)}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
