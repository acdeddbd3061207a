import { useMemo, useRef, useState } from 'react';
import uPlot from 'uplot';
import type { Benchmark, CurriculumEntry, MetricRequirement, Score } from '../../api';
import { useUplot, type ChartMaker } from '../../use_uplot';
import { format_value } from '../common/format';

const chart_height = 220;
const colors = { line: '#0f5e66', passed: '#1e6b34', failed: '#b3261e', threshold: '#c98a00', experts: '#2f6fd6' };

/** One attempt at the chosen task: its number (1 = oldest session) and the chosen metric's score. */
interface Attempt {
  number: number;
  score: Score;
}

/**
 * The attempts of `task` in the order of their sessions, oldest first, each with its score of
 * `metric`. Attempts are numbered over all sessions of the task, so that attempt 3 is the same
 * session whichever metric is shown; a session without that metric leaves its number out.
 */
function attempts_of(scores: Score[], task: string, metric: string): Attempt[] {
  const sessions = new Map<number, { first: string; score: Score | null }>();
  for (const s of scores) {
    if (s.task !== task) continue;
    const entry = sessions.get(s.session_id) ?? { first: s.created_at, score: null };
    if (s.created_at < entry.first) entry.first = s.created_at;
    // Should a session hold the metric twice, its latest score is the one that counts.
    if (s.metric === metric && (!entry.score || s.created_at >= entry.score.created_at)) entry.score = s;
    sessions.set(s.session_id, entry);
  }
  // ISO strings of one format sort as times; the session id breaks ties between equal times.
  const ordered = [...sessions.entries()].sort(([a_id, a], [b_id, b]) =>
    a.first === b.first ? a_id - b_id : a.first < b.first ? -1 : 1,
  );
  const attempts: Attempt[] = [];
  ordered.forEach(([, entry], i) => {
    if (entry.score) attempts.push({ number: i + 1, score: entry.score });
  });
  return attempts;
}

/** The curriculum's task of that key (the first curriculum that defines it), for its name and metrics. */
function find_task(curricula: CurriculumEntry[], key: string) {
  for (const c of curricula) {
    for (const m of c.definition.modules) {
      const task = m.tasks.find((t) => t.key === key);
      if (task) return task;
    }
  }
  return undefined;
}

/** The chart: value line, passed and not-passed markers, threshold line and the experts' mean ± sd band. */
function chart_options(
  width: number,
  attempts: Attempt[],
  requirement: MetricRequirement | undefined,
  benchmark: Benchmark | undefined,
  unit: string,
): [uPlot.Options, uPlot.AlignedData] {
  const x = attempts.map((a) => a.number);
  const values = attempts.map((a) => a.score.value);
  const constant = (v: number | undefined) => x.map(() => v ?? null);
  const markers = (passed: boolean) => attempts.map((a) => (a.score.passed === passed ? a.score.value : null));
  const only_points = (stroke: string, fill: string): uPlot.Series => ({
    stroke,
    paths: () => null,
    points: { show: true, size: 9, width: 2, space: 0, stroke, fill },
  });
  const first = x[0] ?? 1;
  const last = x[x.length - 1] ?? 1;
  const options: uPlot.Options = {
    width,
    height: chart_height,
    legend: { show: false },
    cursor: { drag: { x: false, y: false } },
    scales: { x: { time: false, range: () => [first - 0.3, last + 0.3] } },
    axes: [
      { label: 'Attempt', incrs: [1, 2, 5, 10, 20, 50, 100, 200, 500], values: (_, splits) => splits.map(String) },
      { label: unit, size: 60, values: (_, splits) => splits.map((v) => format_value(v, '')) },
    ],
    series: [
      {},
      { label: 'value', stroke: colors.line, width: 2, points: { show: false } },
      { label: 'passed', ...only_points(colors.passed, colors.passed) },
      { label: 'not passed', ...only_points(colors.failed, '#ffffff') },
      { label: 'threshold', stroke: colors.threshold, width: 1.5, dash: [6, 4], points: { show: false } },
      { label: 'experts + sd', stroke: colors.experts, width: 1, dash: [3, 3], points: { show: false } },
      { label: 'experts - sd', stroke: colors.experts, width: 1, dash: [3, 3], points: { show: false } },
    ],
    bands: benchmark ? [{ series: [5, 6], fill: 'rgba(47, 111, 214, 0.12)' }] : [],
  };
  const data: uPlot.AlignedData = [
    x,
    values,
    markers(true),
    markers(false),
    constant(requirement?.threshold.value),
    constant(benchmark && benchmark.mean + benchmark.sd),
    constant(benchmark && benchmark.mean - benchmark.sd),
  ];
  return [options, data];
}

/**
 * One trainee's progress over their attempts at a task: a chosen metric per attempt against the
 * task's threshold and the experts' mean ± sd. The chart is for the eye; the sentence under it and
 * the table behind "Show the numbers" carry the same values for screen readers and tests.
 */
export function ProgressChart({
  scores,
  curricula,
  benchmarks,
}: {
  scores: Score[];
  curricula: CurriculumEntry[];
  benchmarks: Benchmark[];
}) {
  const [chosen_task, set_task] = useState('');
  const [chosen_metric, set_metric] = useState('');
  const plot_ref = useRef<HTMLDivElement>(null);

  const task_options = useMemo(() => {
    const keys = [...new Set(scores.map((s) => s.task))];
    return keys
      .map((key) => ({ key, label: find_task(curricula, key)?.name ?? key }))
      .sort((a, b) => a.label.localeCompare(b.label));
  }, [scores, curricula]);
  // Until the person picks one, the task of the latest score is shown.
  const latest = scores.reduce<Score | undefined>((l, s) => (!l || s.created_at > l.created_at ? s : l), undefined);
  const task = task_options.some((t) => t.key === chosen_task) ? chosen_task : (latest?.task ?? '');
  const definition = find_task(curricula, task);

  // The curriculum's order of metrics first, then any others that were scored.
  const metric_options = useMemo(() => {
    const scored = new Set(scores.filter((s) => s.task === task).map((s) => s.metric));
    const listed = (definition?.metrics ?? []).map((m) => m.key).filter((k) => scored.has(k));
    return [...listed, ...[...scored].filter((k) => !listed.includes(k)).sort()];
  }, [scores, task, definition]);
  const metric = metric_options.includes(chosen_metric) ? chosen_metric : (metric_options[0] ?? '');

  const attempts = useMemo(() => attempts_of(scores, task, metric), [scores, task, metric]);
  const requirement = definition?.metrics?.find((m) => m.key === metric);
  const benchmark = benchmarks.find((b) => b.task === task && b.metric === metric);
  const unit = attempts[0]?.score.unit ?? requirement?.unit ?? benchmark?.unit ?? '';

  const make: ChartMaker | null =
    attempts.length === 0
      ? null
      : (width) => {
          const [options, data] = chart_options(width, attempts, requirement, benchmark, unit);
          return { options, data };
        };
  useUplot(plot_ref, make, chart_height, [attempts, requirement, benchmark, unit]);

  if (task_options.length === 0) {
    return (
      <div className="progress-chart" data-testid="progress-chart">
        <p className="empty">No scored attempts yet.</p>
      </div>
    );
  }

  const last = attempts[attempts.length - 1];
  const summary = [
    last ? `Attempt ${last.number}: ${format_value(last.score.value, unit)}` : 'No attempts with this metric',
    requirement ? ` (threshold ${requirement.threshold.op} ${format_value(requirement.threshold.value, unit)})` : '',
    benchmark ? `; experts ${format_value(benchmark.mean, '')} ± ${format_value(benchmark.sd, unit)}` : '',
    '.',
  ].join('');

  return (
    <div className="progress-chart" data-testid="progress-chart">
      <div className="form-row progress-controls">
        <div>
          <label htmlFor="progress-task">Task</label>
          <select id="progress-task" data-testid="progress-task" value={task} onChange={(e) => set_task(e.target.value)}>
            {task_options.map((t) => (
              <option key={t.key} value={t.key}>
                {t.label}
              </option>
            ))}
          </select>
        </div>
        <div>
          <label htmlFor="progress-metric">Metric</label>
          <select id="progress-metric" data-testid="progress-metric" value={metric} onChange={(e) => set_metric(e.target.value)}>
            {metric_options.map((m) => (
              <option key={m} value={m}>
                {m}
              </option>
            ))}
          </select>
        </div>
      </div>
      <div className="progress-plot" ref={plot_ref} aria-hidden="true" />
      <ul className="progress-legend" aria-hidden="true">
        <li className="legend-passed">passed</li>
        <li className="legend-failed">not passed</li>
        {requirement && <li className="legend-threshold">threshold</li>}
        {benchmark && <li className="legend-experts">experts (mean ± sd)</li>}
      </ul>
      <p className="progress-summary" data-testid="progress-summary">
        {summary}
      </p>
      <details className="progress-numbers">
        <summary>Show the numbers</summary>
        <table data-testid="progress-table">
          <caption className="visually-hidden">{`${definition?.name ?? task}, ${metric} per attempt`}</caption>
          <thead>
            <tr>
              <th scope="col" className="numeric">Attempt</th>
              <th scope="col" className="numeric">Value</th>
              <th scope="col">Passed</th>
            </tr>
          </thead>
          <tbody>
            {attempts.map((a) => (
              <tr key={a.score.id}>
                <td className="numeric">{a.number}</td>
                <td className="numeric">{format_value(a.score.value, unit)}</td>
                <td>{a.score.passed ? 'Yes' : 'No'}</td>
              </tr>
            ))}
          </tbody>
        </table>
      </details>
    </div>
  );
}
