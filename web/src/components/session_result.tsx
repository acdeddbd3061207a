import { useCallback } from 'react';
import { api, type Score } from '../api';
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
  const scores = useResource(load_scores);
  const recordings = useResource(load_recordings);

  function reload() {
    scores.reload();
    recordings.reload();
  }

  return (
    <Card id="result" title="Result">
      <ResourceView resource={scores} what="scores" empty="No scores are stored for this session yet.">
        {(data) => (
          <>
            <Verdict scores={data} />
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

/** Whether the attempt passed: every metric it was scored on met its threshold. */
function Verdict({ scores }: { scores: Score[] }) {
  const missed = scores.filter((s) => !s.passed);
  return (
    <p className={`verdict ${missed.length === 0 ? 'verdict-pass' : 'verdict-fail'}`} data-testid="attempt-verdict">
      {missed.length === 0
        ? `Passed: all ${scores.length} metrics met their thresholds.`
        : `Not passed: ${missed.map((s) => s.metric).join(', ')} missed ${missed.length === 1 ? 'its threshold' : 'their thresholds'}.`}
    </p>
  );
}
