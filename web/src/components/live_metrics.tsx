import type { StreamMetrics } from '../stream';

const state_labels: Record<StreamMetrics['state'], string> = {
  running: 'Running',
  paused: 'Paused',
  finished: 'Finished',
};

function seconds(value: number): string {
  return `${value.toFixed(1)} s`;
}

interface Row {
  /** The element's data-testid is "metric-<key>". */
  key: string;
  label: string;
  value: (metrics: StreamMetrics, fps: number | null) => string;
}

const rows: Row[] = [
  { key: 'state', label: 'State', value: (m) => state_labels[m.state] ?? m.state },
  {
    key: 'sim_time_s',
    label: 'Simulated time',
    value: (m) => (m.duration_s === undefined ? seconds(m.sim_time_s) : `${seconds(m.sim_time_s)} of ${seconds(m.duration_s)}`),
  },
  { key: 'force_n', label: 'Force', value: (m) => `${m.force_n.toFixed(2)} N` },
  { key: 'peak_force_n', label: 'Peak force', value: (m) => `${m.peak_force_n.toFixed(2)} N` },
  { key: 'path_length_m', label: 'Path length', value: (m) => `${m.path_length_m.toFixed(3)} m` },
  { key: 'contact', label: 'Tool contact', value: (m) => (m.contact ? 'Yes' : 'No') },
  { key: 'agent_online', label: 'Station agent', value: (m) => (m.agent_online ? 'Online' : 'Offline') },
  { key: 'fps', label: 'Frames per second (here)', value: (_, fps) => (fps === null ? '—' : fps.toFixed(1)) },
];

/**
 * The latest metrics message as a list; "—" until the first one arrives. Replays leave out the
 * station agent, which only matters while a session is live.
 */
export function LiveMetrics({ metrics, fps, replay }: { metrics: StreamMetrics | null; fps: number | null; replay: boolean }) {
  const shown = replay ? rows.filter((row) => row.key !== 'agent_online') : rows;
  return (
    <dl className="metrics" aria-label={replay ? 'Replay metrics' : 'Live metrics'}>
      {shown.map((row) => (
        <div key={row.key} className="metric">
          <dt>{row.label}</dt>
          <dd data-testid={`metric-${row.key}`}>{metrics ? row.value(metrics, fps) : '—'}</dd>
        </div>
      ))}
      {metrics?.state === 'paused' && metrics.reason && (
        <div className="metric">
          <dt>Paused because</dt>
          <dd data-testid="metric-reason">{metrics.reason}</dd>
        </div>
      )}
    </dl>
  );
}
