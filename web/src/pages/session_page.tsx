import { useCallback, useState } from 'react';
import { api, type LiveSession, type LiveState } from '../api';
import { ErrorAlert, StatusMessage } from '../components/common/alerts';
import { SessionControls } from '../components/live/session_controls';
import { StaleWarning } from '../components/live/stale_warning';
import { SessionResult } from '../components/review/session_result';
import { StreamView } from '../components/live/stream_view';
import { useFrameStream } from '../use_frame_stream';
import { useResource } from '../use_resource';
import { usePageTitle } from '../use_page_title';

/** `/sessions/{id}`: a live session's picture, metrics and controls; its result once it ended. */
export function SessionPage({ id }: { id: number }) {
  usePageTitle(`Session #${id}`);
  const load = useCallback(() => api.session(id), [id]);
  const session = useResource(['sessions', id], load);
  const data = session.data;

  return (
    <main id="main" tabIndex={-1} className="page">
      <h1>Session #{id}</h1>
      <ErrorAlert message={session.error && `Could not load session #${id}: ${session.error}`} />
      {session.loading && !data && (
        <p className="muted" role="status">
          Loading the session…
        </p>
      )}
      {data && <SessionSummary session={data} />}
      {data?.live && <LiveView session={data} live={data.live} />}
      {data && !data.live && (
        <>
          <p className="muted">This session is no longer live.</p>
          <SessionResult session={data} />
        </>
      )}
    </main>
  );
}

function SessionSummary({ session }: { session: LiveSession }) {
  return (
    <p className="muted">
      Task <strong>{session.task}</strong> at {session.station ?? 'a removed station'} · Trainee: {session.trainee}
    </p>
  );
}

function LiveView({ session, live }: { session: LiveSession; live: LiveState }) {
  const stream = useFrameStream(`/api/sessions/${session.id}/view`);
  const [stopped, set_stopped] = useState(false);
  const state = stream.metrics?.state ?? live.state;
  const agent_online = stream.metrics?.agent_online ?? live.agent_online;
  const ended = stream.ended_reason !== null || state === 'finished' || stopped;

  return (
    <>
      {!agent_online && !ended && (
        <p role="alert" className="alert alert-error" data-testid="agent-offline">
          The station's agent is offline, so the session is paused. Start the agent on the station's computer,
          then resume.
        </p>
      )}
      {!ended && <StaleWarning metrics={stream.metrics} picture_age_s={stream.picture_age_s} />}
      <section className="card" aria-label="Live picture">
        <StreamView stream={stream} test_id="live-canvas" label={`Live picture of session ${session.id}`} replay={false} />
        {state !== 'finished' && !ended && (
          <SessionControls
            session_id={session.id}
            state={state}
            on_done={(next) => set_stopped(next.live === null || next.live.state === 'finished')}
          />
        )}
      </section>
      {ended && (
        <>
          <StatusMessage message={`The session has ended${stream.ended_reason ? `: ${stream.ended_reason}` : ''}.`} />
          {/* Remounted when the Stop answer arrives: the score is stored by then. */}
          <SessionResult key={String(stopped)} session={session} />
        </>
      )}
    </>
  );
}
