import { useCallback } from 'react';
import { api, type Progress, type Score, type ScoreAdjustment, type Session } from '../../api';
import { format_metric, metric_name, useMetricCatalogue, type MetricCatalogue } from '../../metrics';
import { Link } from '../../router';
import { useResource } from '../../use_resource';
import { Card } from '../common/card';
import { ResourceView } from '../common/resource_view';
import { ScoresTable } from './scores_table';
import './review.css';

/** The scores stored for a finished session, where the trainee now stands, and its recording. */
export function SessionResult({ session }: { session: Session }) {
  const session_id = session.id;
  const trainee_id = session.trainee_id;
  const load_scores = useCallback(
    // In the order they were stored, which is the order the task scores them (criteria first).
    () => api.scores().then((scores) => scores.filter((s) => s.session_id === session_id).sort((a, b) => a.id - b.id)),
    [session_id],
  );
  const load_recordings = useCallback(
    () => api.recordings().then((recordings) => recordings.filter((r) => r.session_id === session_id)),
    [session_id],
  );
  const load_adjustments = useCallback(() => api.adjustments(session_id), [session_id]);
  const load_progress = useCallback(() => api.trainee_progress(trainee_id), [trainee_id]);
  const scores = useResource(['scores', { session_id }], load_scores);
  const recordings = useResource(['recordings', { session_id }], load_recordings);
  const adjustments = useResource(['sessions', session_id, 'adjustments'], load_adjustments);
  const progress = useResource(['trainees', trainee_id, 'progress'], load_progress);
  const benchmarks = useResource(['benchmarks'], api.benchmarks);
  // The verdict is the server's (GET /api/sessions/{id} "passed"), asked when this mounts, after
  // the session ended and was scored. Its own key: the live page keeps its answer from before the
  // end (the picture stays up beside the result).
  const load_verdict = useCallback(() => api.session(session_id), [session_id]);
  const verdict = useResource(['sessions', session_id, 'verdict'], load_verdict);
  const catalogue = useMetricCatalogue();

  function reload() {
    verdict.reload();
    scores.reload();
    recordings.reload();
    adjustments.reload();
    progress.reload();
  }

  return (
    <Card id="result" title="Result">
      <ResourceView resource={scores} what="scores" empty="No scores are stored for this session yet.">
        {(data) => (
          <>
            <Verdict
              passed={verdict.data?.passed ?? null}
              scores={data}
              adjustment={adjustments.data?.at(-1) ?? null}
              catalogue={catalogue}
            />
            {progress.data && <Standing progress={progress.data} task={session.task} />}
            <CompletionCriteria scores={data.filter((s) => s.criterion)} catalogue={catalogue} />
            <ScoresTable
              scores={data.filter((s) => !s.criterion)}
              show_trainee={false}
              in_session
              benchmarks={benchmarks.data ?? []}
            />
          </>
        )}
      </ResourceView>
      <ResourceView resource={recordings} what="recordings" empty="No recording is stored for this session yet.">
        {(data) => (
          <ul className="plain-list">
            {data.map((r) => (
              <li key={r.id}>
                <Link to={`/recordings/${r.id}`}>Watch the recording of this session</Link> ({r.duration_s.toFixed(1)} s)
              </li>
            ))}
          </ul>
        )}
      </ResourceView>
      <button type="button" className="button-quiet button-small" onClick={reload}>
        Refresh
      </button>
    </Card>
  );
}

/**
 * Whether the attempt passed, as the server decided (null while it does not know yet), said with
 * its reasons: the instructor's adjustment, the criteria not met, or the metrics that missed.
 */
export function Verdict({
  passed,
  scores,
  adjustment,
  catalogue,
}: {
  passed: boolean | null;
  scores: Score[];
  adjustment: ScoreAdjustment | null;
  catalogue: MetricCatalogue | null;
}) {
  if (passed === null) {
    return (
      <p className="muted" role="status">
        Working out the result…
      </p>
    );
  }
  const missed = scores.filter((s) => !s.passed);
  let text: string;
  if (adjustment) {
    text = `${passed ? 'Passed' : 'Not passed'}, as adjusted by ${adjustment.author}: ${adjustment.reason}`;
  } else if (passed) {
    text = `Passed: the task was done and all ${scores.filter((s) => !s.criterion).length} metrics met their thresholds.`;
  } else if (missed.some((s) => s.criterion)) {
    const undone = missed.filter((s) => s.criterion).map((s) => metric_name(catalogue, s.metric).toLowerCase());
    text = `Not passed: the task was not done (${undone.join('; ')}), whatever the other metrics.`;
  } else {
    const names = missed.map((s) => metric_name(catalogue, s.metric).toLowerCase());
    text = `Not passed: ${names.join(', ')} missed ${missed.length === 1 ? 'its threshold' : 'their thresholds'}.`;
  }
  return (
    <p className={`verdict ${passed ? 'verdict-pass' : 'verdict-fail'}`} data-testid="attempt-verdict">
      {text}
    </p>
  );
}

/**
 * Where the trainee stands with the task after this attempt, from the server's progress:
 * "2 of 3 passes in a row" toward mastering it, or mastered, and the task to work on next.
 */
function Standing({ progress, task }: { progress: Progress; task: string }) {
  const entry = progress.tasks.find((t) => t.key === task);
  if (!entry) return null;
  const next = progress.tasks.find((t) => t.key === progress.next_task);
  const run = entry.mastered
    ? `${entry.name}: mastered`
    : `${entry.name}: ${entry.consecutive_passes} of ${entry.required_passes} passes in a row`;
  const then = next ? (next.key === task ? '' : `; next: ${next.name}`) : '; every task of the curriculum is mastered';
  return (
    <p className="standing" data-testid="attempt-standing">
      {run}
      {then}.
    </p>
  );
}

/** The task's completion criteria and whether the attempt met each, before the thresholds. */
function CompletionCriteria({ scores, catalogue }: { scores: Score[]; catalogue: MetricCatalogue | null }) {
  if (scores.length === 0) return null;
  return (
    <section aria-label="Completion criteria">
      <h3>Completion criteria</h3>
      <ul className="criteria">
        {scores.map((s) => (
          <li key={s.id} className={s.passed ? 'criterion-met' : 'criterion-missed'}>
            <span className={`badge ${s.passed ? 'badge-pass' : 'badge-fail'}`}>{s.passed ? 'Met' : 'Not met'}</span>{' '}
            {metric_name(catalogue, s.metric)}: {format_metric(catalogue, s.metric, s.value, s.unit)}
            {s.threshold && (
              <span className="muted">
                {' '}
                (needed {s.threshold.op === '>=' ? 'at least' : 'at most'}{' '}
                {format_metric(catalogue, s.metric, s.threshold.value, s.unit)})
              </span>
            )}
          </li>
        ))}
      </ul>
    </section>
  );
}
