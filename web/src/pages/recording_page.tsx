import { api, type Recording } from '../api';
import { ErrorAlert } from '../components/alerts';
import { ReplayControls } from '../components/replay_controls';
import { StreamView } from '../components/stream_view';
import { format_date_time } from '../time';
import { useFrameStream } from '../use_frame_stream';
import { useResource } from '../use_resource';

/**
 * `/recordings/{id}`: replays a recorded session. The recording is looked up in the list first: the
 * server refuses the replay socket of an unknown or foreign recording before the upgrade, and a
 * browser cannot read why.
 */
export function RecordingPage({ id }: { id: number }) {
  const recordings = useResource(api.recordings);
  const recording = recordings.data?.find((r) => r.id === id);

  return (
    <main className="page">
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
  const stream = useFrameStream(`/api/recordings/${recording.id}/replay`);
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
        <ReplayControls metrics={stream.metrics} duration_s={recording.duration_s} send={stream.send} />
      </section>
    </>
  );
}
