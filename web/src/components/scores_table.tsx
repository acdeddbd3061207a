import type { Score } from '../api';
import { format_date_time } from '../time';

const large_format = new Intl.NumberFormat(undefined, { maximumFractionDigits: 2 });
const small_format = new Intl.NumberFormat(undefined, { maximumSignificantDigits: 3 });

function format_value(value: number, unit: string): string {
  const shown = (Math.abs(value) >= 1 ? large_format : small_format).format(value);
  return unit ? `${shown} ${unit}` : shown;
}

export function ScoresTable({ scores, show_trainee }: { scores: Score[]; show_trainee: boolean }) {
  return (
    <div className="table-wrap">
      <table>
        <thead>
          <tr>
            <th scope="col">Session</th>
            {show_trainee && <th scope="col">Trainee</th>}
            <th scope="col">Task</th>
            <th scope="col">Metric</th>
            <th scope="col" className="numeric">
              Value
            </th>
            <th scope="col">Result</th>
            <th scope="col">Recorded</th>
          </tr>
        </thead>
        <tbody>
          {scores.map((s) => (
            <tr key={s.id}>
              <td>#{s.session_id}</td>
              {show_trainee && <td>{s.trainee}</td>}
              <td>{s.task}</td>
              <td>{s.metric}</td>
              <td className="numeric">{format_value(s.value, s.unit)}</td>
              <td>
                <span className={`badge ${s.passed ? 'badge-pass' : 'badge-fail'}`}>{s.passed ? 'Passed' : 'Not passed'}</span>
              </td>
              <td>{format_date_time(s.created_at)}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
