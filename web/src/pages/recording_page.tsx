import { useCallback, useMemo, useState } from 'react';
import { api, type Recording } from '../api';
import { useUser } from '../auth';
import { AttemptReview } from '../components/review/attempt_review';
import { ReviewNotes } from '../components/review/review_notes';
import { ErrorAlert } from '../components/common/alerts';
import { ReplayControls } from '../components/review/replay_controls';
import { StreamView } from '../components/live/stream_view';
import { format_date_time } from '../time';
import { useFrameStream } from '../use_frame_stream';
import { error_text, useResource } from '../use_resource';
import { usePageTitle } from '../use_page_title';

/**
 * `/recordings/{id}`: replays a recorded session for review: the replay, its events and timelines
 * (which seek it), its results against thresholds and experts, annotations and score adjustments.
 * The recording is looked up in the list first: the server refuses the replay socket of an unknown
 * or foreign recording before the upgrade, and a browser cannot read why.
 */
export function RecordingPage({ id }: { id: number }) {
  usePageTitle(`Recording #${id}`);
  const recordings = useResource(['recordings'], api.recordings);
  const recording = recordings.data?.find((r) => r.id === id);

  return (
    <main id="main" tabIndex={-1} className="page">
      <h1>Recording #{id}</h1>
      <ErrorAlert message={recordings.error && `Could not load the recordings: ${recordings.error}`} />
      {recordings.loading && !recordings.data && (
        <p className="muted" role="status">
          Loading the recording…
        </p>
      )}
      {recordings.data && !recording && (
        <ErrorAlert message={`There is no recording #${id}, or it belongs to a session you may not see.`} />
      )}
      {recording && <ReplayView recording={recording} />}
    </main>
  );
}

function ReplayView({ recording }: { recording: Recording }) {
  const viewer = useUser();
  const stream = useFrameStream(`/api/recordings/${recording.id}/replay`);
  const { send } = stream;
  const position_s = stream.metrics?.sim_time_s ?? 0;
  const seek = useCallback((t_s: number) => send({ type: 'seek', t: t_s }), [send]);
  // One review for the page: the results, the timelines and the expert switch share it.
  const load_review = useMemo(() => () => api.review(recording.session_id), [recording.session_id]);
  const review = useResource(['sessions', recording.session_id, 'review'], load_review);
  return (
    <>
      <p className="muted">
        Session #{recording.session_id} · task <strong>{recording.task}</strong> · Trainee: {recording.trainee} · recorded{' '}
        {format_date_time(recording.created_at)}
      </p>
      <section className="card" aria-label="Replay">
        <StreamView
          stream={stream}
          test_id="replay-canvas"
          label={`Replay of session ${recording.session_id}`}
          replay
        />
        <ReplayControls metrics={stream.metrics} duration_s={recording.duration_s} send={send} />
      </section>
      <AttemptReview review={review} position_s={position_s} on_seek={seek} />
      <ReviewNotes session_id={recording.session_id} viewer={viewer} position_s={position_s} on_seek={seek} />
      {/* Admins mark any staff attempt; an instructor their own (the server checks both). */}
      {review.data && (viewer.role === 'admin' || (viewer.role === 'instructor' && review.data.trainee_id === viewer.id)) && (
        <ExpertRunToggle session_id={recording.session_id} expert={review.data.expert_run} on_changed={review.reload} />
      )}
    </>
  );
}

/** The expert runs whose scores make each task's benchmark: admins choose, instructors offer their own. */
function ExpertRunToggle({ session_id, expert, on_changed }: { session_id: number; expert: boolean; on_changed: () => void }) {
  const [error, set_error] = useState<string | null>(null);
  const [busy, set_busy] = useState(false);

  async function toggle() {
    set_busy(true);
    set_error(null);
    try {
      await api.set_expert_run(session_id, !expert);
      on_changed();
    } catch (reason) {
      set_error(`Could not change the expert run: ${error_text(reason)}`);
    } finally {
      set_busy(false);
    }
  }

  return (
    <section className="card" aria-labelledby="expert-title">
      <h2 id="expert-title">Expert benchmark</h2>
      <p>
        {expert
          ? 'This attempt is an expert run: its scores are part of the task’s benchmark.'
          : 'Mark this attempt (an instructor’s or an admin’s) as an expert run to add its scores to the task’s benchmark.'}
      </p>
      <ErrorAlert message={error} />
      <button type="button" disabled={busy} onClick={() => void toggle()}>
        {expert ? 'Remove from the benchmark' : 'Mark as expert run'}
      </button>
    </section>
  );
}
