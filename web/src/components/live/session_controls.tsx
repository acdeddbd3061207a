import { useState } from 'react';
import { api, type LiveSession, type SessionAction } from '../../api';
import { error_text } from '../../use_resource';
import { ErrorAlert } from '../common/alerts';

const action_labels: Record<SessionAction, string> = { pause: 'Pause', resume: 'Resume', stop: 'Stop' };
const busy_labels: Record<SessionAction, string> = { pause: 'Pausing…', resume: 'Resuming…', stop: 'Stopping…' };

/**
 * Pause or Resume (whichever applies to `state`) and Stop. The new state reaches the page through
 * the stream's metrics; `on_done` receives the server's answer, e.g. to learn the recording.
 */
export function SessionControls({
  session_id,
  state,
  on_done,
}: {
  session_id: number;
  state: 'running' | 'paused';
  on_done: (session: LiveSession) => void;
}) {
  const [busy, set_busy] = useState<SessionAction | null>(null);
  const [error, set_error] = useState<string | null>(null);

  async function run(action: SessionAction) {
    if (action === 'stop' && !window.confirm('Stop the session? It is scored as it stands and cannot be continued.')) return;
    set_busy(action);
    set_error(null);
    try {
      on_done(await api.session_action(session_id, action));
    } catch (reason) {
      // e.g. resuming while the station's agent is offline: the server says so.
      set_error(`Could not ${action_labels[action].toLowerCase()} the session: ${error_text(reason)}`);
    } finally {
      set_busy(null);
    }
  }

  const toggle: SessionAction = state === 'running' ? 'pause' : 'resume';
  return (
    <div aria-label="Session controls" role="group">
      <div className="button-row">
        <button type="button" className="button-primary" disabled={busy !== null} onClick={() => run(toggle)}>
          {busy === toggle ? busy_labels[toggle] : action_labels[toggle]}
        </button>
        <button type="button" className="button-danger" disabled={busy !== null} onClick={() => run('stop')}>
          {busy === 'stop' ? busy_labels.stop : action_labels.stop}
        </button>
      </div>
      <ErrorAlert message={error} />
    </div>
  );
}
