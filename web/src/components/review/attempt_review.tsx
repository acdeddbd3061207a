import { useMemo } from 'react';
import type { Review, ReviewResult, RunEvent } from '../../api';
import type { Resource } from '../../use_resource';
import { ErrorAlert } from '../common/alerts';
import './review.css';
import { DataTable } from '../common/data_table';
import { format_metric, useMetricCatalogue, type MetricCatalogue } from '../../metrics';
import { format_seconds } from '../common/format';
import { MetricLabel } from './scores_table';
import { event_colors, TimelineChart, type TimelineSeries } from './timeline_chart';

const event_names: Record<RunEvent['kind'], string> = {
  contact: 'Contact',
  grasp: 'Grasp',
  release: 'Release',
  cut: 'Cut',
  collision: 'Collision',
  never_event: 'Never event',
  target: 'Target reached',
};

const hand_names = ['right hand', 'left hand'];

/** One chart under the replay: a signal of the attempt over time. */
interface ChartSpec {
  test_id: string;
  title: string;
  unit: string;
  t_s: number[];
  series: TimelineSeries[];
}
const hand_colors = ['#2f6fb3', '#d9822b'];

/**
 * An attempt's events and signals under its replay: event markers that jump the replay, force,
 * speed and tissue damage over time, and each metric against its threshold and the experts.
 */
export function AttemptReview({
  review,
  position_s,
  on_seek,
}: {
  review: Resource<Review>;
  position_s: number;
  on_seek: (t_s: number) => void;
}) {
  return (
    <>
      <ErrorAlert message={review.error && `Could not load the review: ${review.error}`} />
      {review.loading && !review.data && (
        <p className="muted" role="status">
          Loading the review…
        </p>
      )}
      {review.data && <ReviewBody review={review.data} position_s={position_s} on_seek={on_seek} />}
    </>
  );
}

function ReviewBody({ review, position_s, on_seek }: { review: Review; position_s: number; on_seek: (t: number) => void }) {
  const { timeline } = review;
  // Stable arrays: a new one would rebuild the charts on every frame's metrics.
  const charts = useMemo((): ChartSpec[] => {
    const per_hand = (pick: (h: Review['timeline']['hands'][number]) => number[], scale = 1): TimelineSeries[] =>
      timeline.hands.map((h, i) => ({
        label: hand_names[i] ?? `hand ${i}`,
        values: pick(h).map((v) => v * scale),
        color: hand_colors[i] ?? '#555',
      }));
    const specs: ChartSpec[] = [
      { test_id: 'timeline-force', title: 'Peak force', unit: 'N', t_s: timeline.t_s, series: per_hand((h) => h.peak_force_n) },
      { test_id: 'timeline-speed', title: 'Tip speed', unit: 'mm/s', t_s: timeline.t_s, series: per_hand((h) => h.speed_m_s, 1000) },
    ];
    const signal = review.sim_damage;
    if (signal && signal.values.length > 0) {
      specs.push({
        test_id: 'timeline-sim-damage',
        title: 'Tissue damage (simulation: tissue strained beyond its threshold)',
        unit: '% volume',
        t_s: signal.values.map((_, i) => (i + 1) * signal.interval_s),
        series: [{ label: 'damaged volume', values: signal.values.map((v) => v * 100), color: '#7f0000' }],
      });
    }
    specs.push({
      test_id: 'timeline-damage',
      title: 'Tissue overload (force above the safe force)',
      unit: 'N s',
      t_s: timeline.t_s,
      series: [{ label: 'cumulative', values: timeline.damage_ns, color: '#c0392b' }],
    });
    return specs;
  }, [timeline, review.sim_damage]);

  return (
    <>
      <section className="card" aria-labelledby="events-title">
        <h2 id="events-title">Events</h2>
        {review.events.length === 0 ? (
          <p className="muted">No events in this attempt.</p>
        ) : (
          <ul className="event-list" aria-label="Event markers">
            {review.events.map((e, i) => (
              <li key={i}>
                <button
                  type="button"
                  className="event-marker"
                  data-testid="event-marker"
                  data-kind={e.kind}
                  data-source={e.source}
                  title={e.label}
                  style={{ borderColor: event_colors[e.kind] }}
                  aria-label={`Jump to ${event_names[e.kind].toLowerCase()} at ${format_seconds(e.t_s)}: ${e.label}`}
                  onClick={() => on_seek(e.t_s)}
                >
                  <span className="event-dot" style={{ background: event_colors[e.kind] }} />
                  {event_names[e.kind]} · {format_seconds(e.t_s)} · {hand_names[e.hand] ?? 'no hand'}
                </button>
              </li>
            ))}
          </ul>
        )}
      </section>
      <section className="card" aria-labelledby="timelines-title">
        <h2 id="timelines-title">Timelines</h2>
        <p className="hint">
          Click a chart to jump the replay there, or focus it and use the arrow keys (Home, End: start,
          end); the black line is the replay's position.
        </p>
        {charts.map((chart) => (
          <TimelineChart
            key={chart.test_id}
            {...chart}
            duration_s={review.duration_s}
            events={review.events}
            position_s={position_s}
            on_seek={on_seek}
          />
        ))}
      </section>
      <section className="card" aria-labelledby="results-title">
        <h2 id="results-title">Results</h2>
        <ResultsTable results={review.results} />
      </section>
    </>
  );
}

function expert_text(catalogue: MetricCatalogue | null, r: ReviewResult): string {
  if (!r.expert) return '—';
  const { mean, sd, n, z } = r.expert;
  const spread = n > 1 ? ` ± ${format_metric(catalogue, r.metric, sd, r.unit)}` : '';
  const relative = z === null ? '' : ` (${z >= 0 ? '+' : ''}${z.toFixed(1)} SD)`;
  return `${format_metric(catalogue, r.metric, mean, r.unit)}${spread}, n = ${n}${relative}`;
}

function ResultsTable({ results }: { results: ReviewResult[] }) {
  const catalogue = useMetricCatalogue();
  const shown = (r: ReviewResult, value: number) => format_metric(catalogue, r.metric, value, r.unit);
  if (results.length === 0) return <p className="muted">This attempt has no scores.</p>;
  return (
    <DataTable<ReviewResult>
      rows={results}
      row_key={(r) => r.metric}
      labelled_by="results-title"
      columns={[
        { header: 'Metric', cell: (r) => <MetricLabel catalogue={catalogue} metric={r.metric} /> },
        { header: 'Value', className: 'numeric', cell: (r) => shown(r, r.value) },
        {
          header: 'Threshold',
          className: 'numeric',
          cell: (r) => {
            if (!r.threshold) return '—';
            const then = `${r.threshold.op} ${shown(r, r.threshold.value)}`;
            if (!r.threshold_now) return then;
            return `${then} (now ${r.threshold_now.op} ${shown(r, r.threshold_now.value)})`;
          },
        },
        {
          header: 'Result',
          cell: (r) => (
            <span className={`badge ${r.passed ? 'badge-pass' : 'badge-fail'}`}>{r.passed ? 'Passed' : 'Not passed'}</span>
          ),
        },
        { header: 'Experts (mean ± SD)', cell: (r) => expert_text(catalogue, r) },
      ]}
    />
  );
}
