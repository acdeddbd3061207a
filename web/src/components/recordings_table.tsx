import type { Recording } from '../api';
import { Link } from '../router';
import { format_date_time } from '../time';

export function RecordingsTable({ recordings, show_trainee }: { recordings: Recording[]; show_trainee: boolean }) {
  return (
    <div className="table-wrap">
      <table>
        <thead>
          <tr>
            <th scope="col">Session</th>
            {show_trainee && <th scope="col">Trainee</th>}
            <th scope="col">Task</th>
            <th scope="col" className="numeric">
              Duration
            </th>
            <th scope="col">Recorded</th>
            <th scope="col">
              <span className="visually-hidden">Actions</span>
            </th>
          </tr>
        </thead>
        <tbody>
          {recordings.map((r) => (
            <tr key={r.id}>
              <td>#{r.session_id}</td>
              {show_trainee && <td>{r.trainee}</td>}
              <td>{r.task}</td>
              <td className="numeric">{r.duration_s.toFixed(1)} s</td>
              <td>{format_date_time(r.created_at)}</td>
              <td className="actions">
                <Link to={`/recordings/${r.id}`} label={`Replay the recording of session ${r.session_id}`}>
                  Replay
                </Link>
              </td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
