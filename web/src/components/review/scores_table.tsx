import type { Benchmark, Score } from '../../api';
import { format_metric, metric_name, useMetricCatalogue, type MetricCatalogue } from '../../metrics';
import { format_date_time } from '../../time';
import { DataTable } from '../common/data_table';

/** A metric's name as people read it, with its key (what curricula and exports use) beside it. */
export function MetricLabel({ catalogue, metric }: { catalogue: MetricCatalogue | null; metric: string }) {
  const info = catalogue?.get(metric);
  return (
    <span title={info?.definition}>
      {metric_name(catalogue, metric)} {info && <code className="metric-key">{metric}</code>}
    </span>
  );
}

/**
 * Scores as a table. `in_session`: one attempt's scores, with the threshold each was judged
 * against and the experts' band (`benchmarks`) instead of the session, task and time columns.
 */
export function ScoresTable({
  scores,
  show_trainee,
  in_session = false,
  benchmarks = [],
}: {
  scores: Score[];
  show_trainee: boolean;
  in_session?: boolean;
  benchmarks?: Benchmark[];
}) {
  const catalogue = useMetricCatalogue();
  const expert = (s: Score) => benchmarks.find((b) => b.task === s.task && b.metric === s.metric);
  return (
    <DataTable<Score>
      rows={scores}
      row_key={(s) => s.id}
      columns={[
        !in_session && { header: 'Session', cell: (s) => `#${s.session_id}` },
        show_trainee && { header: 'Trainee', cell: (s) => s.trainee },
        !in_session && { header: 'Task', cell: (s) => s.task },
        { header: 'Metric', cell: (s) => <MetricLabel catalogue={catalogue} metric={s.metric} /> },
        { header: 'Value', className: 'numeric', cell: (s) => format_metric(catalogue, s.metric, s.value, s.unit) },
        in_session && {
          header: 'Threshold',
          className: 'numeric',
          cell: (s) =>
            s.threshold ? `${s.threshold.op === '<=' ? '≤' : '≥'} ${format_metric(catalogue, s.metric, s.threshold.value, s.unit)}` : '—',
        },
        in_session && {
          header: 'Experts (mean ± SD)',
          className: 'numeric',
          cell: (s) => {
            const b = expert(s);
            if (!b) return '—';
            const mean = format_metric(catalogue, s.metric, b.mean, b.unit);
            return b.n > 1 ? `${mean} ± ${format_metric(catalogue, s.metric, b.sd, b.unit)}, n = ${b.n}` : `${mean}, n = 1`;
          },
        },
        {
          header: 'Result',
          cell: (s) => (
            <span className={`badge ${s.passed ? 'badge-pass' : 'badge-fail'}`}>{s.passed ? 'Passed' : 'Not passed'}</span>
          ),
        },
        !in_session && { header: 'Recorded', cell: (s) => format_date_time(s.created_at) },
      ]}
    />
  );
}
