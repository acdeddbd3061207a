import { useState } from 'react';
import type { FrameStream } from '../../use_frame_stream';
import { default_view } from '../../use_frame_stream';
import { ErrorAlert, StatusMessage } from '../common/alerts';
import { LiveMetrics } from './live_metrics';

/** The streamed picture with the metrics beside it, and what became of the connection. */
export function StreamView({
  stream,
  test_id,
  label,
  replay,
}: {
  stream: FrameStream;
  /** data-testid of the canvas. */
  test_id: string;
  /** What the picture shows, for screen readers. */
  label: string;
  replay: boolean;
}) {
  // The canvas's ref apart from the values that are rendered (React's rules for refs).
  const { canvas_ref, metrics, fps } = stream;
  return (
    <>
      <div className="stream-layout">
        <div className="stream-picture">
          <canvas
            ref={canvas_ref}
            className="stream-canvas"
            width={default_view.width}
            height={default_view.height}
            role="img"
            aria-label={label}
            data-testid={test_id}
          />
        </div>
        <LiveMetrics metrics={metrics} fps={fps} replay={replay} />
      </div>
      {metrics?.outside_view_allowed && <CameraSwitch stream={stream} />}
      <StreamStatus stream={stream} />
    </>
  );
}

/** The picture's camera: the scope the trainee sees through, or the view from outside the body. */
function CameraSwitch({ stream }: { stream: FrameStream }) {
  const [view, set_view] = useState<'scope' | 'outside'>('scope');
  const choose = (next: 'scope' | 'outside') => {
    if (stream.phase !== 'open') return;
    set_view(next);
    stream.send({ type: 'configure', view: next });
  };
  return (
    <div className="camera-switch" role="group" aria-label="Camera">
      <span className="muted">Camera:</span>
      <button type="button" aria-pressed={view === 'scope'} onClick={() => choose('scope')}>
        Scope
      </button>
      <button type="button" aria-pressed={view === 'outside'} onClick={() => choose('outside')}>
        Outside view
      </button>
    </div>
  );
}

function StreamStatus({ stream }: { stream: FrameStream }) {
  const { phase, close, ended_reason, bad_frames } = stream;
  return (
    <>
      {phase === 'connecting' && (
        <p className="muted" role="status">
          Connecting to the picture stream…
        </p>
      )}
      {phase === 'closed' && ended_reason === null && close && (
        // A normal closure (1000) is the server's choice, e.g. at the end of a replay; anything
        // else means the picture stopped against the person's will.
        close.code === 1000 ? <StatusMessage message={close_message(close)} /> : <ErrorAlert message={close_message(close)} />
      )}
      {bad_frames > 0 && (
        <p className="hint" role="status">
          {bad_frames} {bad_frames === 1 ? 'frame' : 'frames'} could not be shown.
        </p>
      )}
    </>
  );
}

function close_message({ code, reason }: { code: number; reason: string }): string {
  // 1006 is the browser's code for a connection that ended without a close frame; it is also all a
  // page learns when the server refuses the upgrade (403, 404).
  const why = reason || (code === 1006 ? 'the connection was lost or refused' : 'no reason given');
  return `The picture stream closed: ${why} (code ${code}). Reload the page to connect again.`;
}
