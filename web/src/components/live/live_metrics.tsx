import type { StreamMetrics } from '../../stream';

const state_labels: Record<StreamMetrics['state'], string> = {
  running: 'Running',
  paused: 'Paused',
  finished: 'Finished',
};

function percent(share: number): string {
  return `${(share * 100).toFixed(1)} %`;
}

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
  {
    key: 'state',
    label: 'State',
    value: (m) => {
      const label = state_labels[m.state];
      return m.state === 'running' && m.behind_real_time ? `${label}, behind real time` : label;
    },
  },
  {
    key: 'pace',
    label: 'Pace',
    value: (m) => {
      if (m.real_time_factor === undefined) return '—';
      const parts = [`${m.real_time_factor.toFixed(2)}x real time`];
      // "Behind" holds until the session has kept up for a while (the server's hysteresis); the
      // lag shows only while there is one.
      if (m.behind_real_time && m.lag_ms !== undefined && m.lag_ms >= 1) parts.push(`${m.lag_ms.toFixed(0)} ms behind`);
      if (m.shed) parts.push(m.shed);
      return parts.join(', ');
    },
  },
  {
    key: 'sim_time_s',
    label: 'Simulated time',
    value: (m) => (m.duration_s === undefined ? seconds(m.sim_time_s) : `${seconds(m.sim_time_s)} of ${seconds(m.duration_s)}`),
  },
  { key: 'force_n', label: 'Force', value: (m) => `${m.force_n.toFixed(2)} N` },
  { key: 'peak_force_n', label: 'Peak force', value: (m) => `${m.peak_force_n.toFixed(2)} N` },
  { key: 'path_length_m', label: 'Path length', value: (m) => `${m.path_length_m.toFixed(3)} m` },
  {
    key: 'damage_index',
    label: 'Tissue damaged',
    value: (m) => `${((m.damage_index ?? 0) * 100).toFixed(2)} %`,
  },
  {
    key: 'cut',
    label: 'Cut',
    value: (m) =>
      `${((m.cut_area_m2 ?? 0) * 1e6).toFixed(1)} mm², ${((m.cut_mean_distance_m ?? 0) * 1e3).toFixed(1)} mm from the line on average`,
  },
  {
    key: 'never_event',
    label: 'Protected structure cut',
    value: (m) => (m.never_event ? 'Yes: never event' : 'No'),
  },
  {
    key: 'tissue_recovery',
    label: 'Tangled tissue recovered',
    value: (m) => (m.inverted_tets_pulled ? `Yes (${m.inverted_tets_pulled} element pulls)` : 'No'),
  },
  { key: 'contact', label: 'Tool contact', value: (m) => (m.contact ? 'Yes' : 'No') },
  {
    key: 'force_2_n',
    label: 'Second tool force',
    value: (m) => (m.force_2_n === undefined ? '—' : `${m.force_2_n.toFixed(2)} N`),
  },
  { key: 'agent_online', label: 'Station agent', value: (m) => (m.agent_online ? 'Online' : 'Offline') },
  {
    key: 'link',
    label: 'Station link',
    value: (m) =>
      m.link
        ? `round trip ${m.link.rtt_p50_ms.toFixed(1)} ms (p99 ${m.link.rtt_p99_ms.toFixed(1)}), loss ${percent(m.link.loss_up ?? 0)} up / ${percent(m.link.loss_down)} down`
        : '—',
  },
  { key: 'haptic_loop', label: 'Haptic loop', value: (m) => (m.link ? `${m.link.loop_hz.toFixed(0)} Hz` : '—') },
  {
    key: 'haptic_devices',
    label: 'Devices (model age, force)',
    value: (m) =>
      m.link && m.link.devices.length > 0
        ? m.link.devices
            .map((d) => `${d.index}: ${d.model_age_ms.toFixed(0)} ms, ${d.fault === 'none' ? `${d.force_n.toFixed(2)} N` : `off (${d.fault})`}`)
            .join('; ')
        : '—',
  },
  { key: 'fps', label: 'Frames per second (here)', value: (_, fps) => (fps === null ? '—' : fps.toFixed(1)) },
];

/**
 * The latest metrics message as a list; "—" until the first one arrives. Replays leave out the
 * station agent and its link, which only matter while a session is live; one-handed sessions
 * leave out the second tool, and scenes that do not cut leave out the cut.
 */
const live_only = new Set(['agent_online', 'pace', 'link', 'haptic_loop', 'haptic_devices']);
/** Rows only a surgical scene (one that cuts) has. */
const surgical_only = new Set(['cut', 'never_event', 'tissue_recovery']);

export function LiveMetrics({ metrics, fps, replay }: { metrics: StreamMetrics | null; fps: number | null; replay: boolean }) {
  const shown = rows.filter(
    (row) =>
      !(replay && live_only.has(row.key)) &&
      !(row.key === 'force_2_n' && (metrics?.hands ?? 1) < 2) &&
      !(surgical_only.has(row.key) && metrics?.cut_area_m2 === undefined),
  );
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
