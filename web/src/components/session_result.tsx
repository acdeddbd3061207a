import { useCallback } from 'react';
import { api, type Score, type ScoreAdjustment } from '../api';
import { Link } from '../router';
import { useResource } from '../use_resource';
import { Card } from './card';
import { ResourceView } from './resource_view';
import { ScoresTable } from './scores_table';
import './review.css';

/** The scores stored for a finished session and a link to its recording. */
export function SessionResult({ session_id }: { session_id: number }) {
  const load_scores = useCallback(
    () => api.scores().then((scores) => scores.filter((s) => s.session_id === session_id)),
    [session_id],
  );
  const load_recordings = useCallback(
    () => api.recordings().then((recordings) => recordings.filter((r) => r.session_id === session_id)),
    [session_id],
  );
  const load_adjustments = useCallback(() => api.adjustments(session_id), [session_id]);
  const scores = useResource(load_scores);
  const recordings = useResource(load_recordings);
  const adjustments = useResource(load_adjustments);

  function reload() {
    scores.reload();
    recordings.reload();
    adjustments.reload();
  }

  return (
    <Card id="result" title="Result">
      <ResourceView resource={scores} what="scores" empty="No scores are stored for this session yet.">
        {(data) => (
          <>
            <Verdict scores={data} adjustment={adjustments.data?.at(-1) ?? null} />
            <ScoresTable scores={data} show_trainee={false} />
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
 * Whether the attempt passed: every metric it was scored on met its threshold, unless an
 * instructor's adjustment (the latest one counts, as in the progress) says otherwise.
 */
function Verdict({ scores, adjustment }: { scores: Score[]; adjustment: ScoreAdjustment | null }) {
  const missed = scores.filter((s) => !s.passed);
  const passed = adjustment ? adjustment.passed : missed.length === 0;
  let text: string;
  if (adjustment) {
    text = `${passed ? 'Passed' : 'Not passed'}, as adjusted by ${adjustment.author}: ${adjustment.reason}`;
  } else if (passed) {
    text = `Passed: all ${scores.length} metrics met their thresholds.`;
  } else {
    text = `Not passed: ${missed.map((s) => s.metric).join(', ')} missed ${missed.length === 1 ? 'its threshold' : 'their thresholds'}.`;
  }
  return (
    <p className={`verdict ${passed ? 'verdict-pass' : 'verdict-fail'}`} data-testid="attempt-verdict">
      {text}
    </p>
  );
}
