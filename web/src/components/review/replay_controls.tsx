import { useEffect, useRef, useState } from 'react';
import type { ClientMessage, StreamMetrics } from '../../stream';

const speeds = [0.25, 0.5, 1, 2, 4];

/**
 * Play/pause, speed and a seek slider for a replay, which opens paused. The slider follows the
 * replay's time from the metrics, except while the person holds it; the seek is sent once, when
 * they let go, and "Seeking to …" shows until the server says it landed.
 */
export function ReplayControls({
  metrics,
  duration_s,
  send,
}: {
  metrics: StreamMetrics | null;
  duration_s: number;
  send: (message: ClientMessage) => void;
}) {
  const [speed, set_speed] = useState(1);
  const [held, set_held] = useState<number | null>(null);
  const seek_ref = useRef<HTMLInputElement>(null);
  const sent_at = useRef(0);
  const playing = metrics?.playing ?? false;
  const duration = metrics?.duration_s ?? duration_s;

  // React's onChange fires on every step of a drag; the DOM's own "change" fires once on release.
  useEffect(() => {
    const slider = seek_ref.current;
    if (!slider) return;
    const commit = () => {
      send({ type: 'seek', t: Number(slider.value) });
      sent_at.current = performance.now();
    };
    slider.addEventListener('change', commit);
    return () => slider.removeEventListener('change', commit);
  }, [send]);

  // Let go of the held position once metrics produced after the seek arrive (they come about ten
  // times a second), so that the slider does not jump back to the time before the seek.
  useEffect(() => {
    if (held !== null && sent_at.current > 0 && performance.now() - sent_at.current > 250) {
      sent_at.current = 0;
      set_held(null);
    }
  }, [metrics, held]);

  function on_speed(value: number) {
    set_speed(value);
    send({ type: 'speed', value });
  }

  const seeking = metrics?.seeking === true;
  const position = held ?? (seeking ? metrics.seek_to_s : undefined) ?? metrics?.sim_time_s ?? 0;
  return (
    <div className="replay-controls" role="group" aria-label="Replay controls">
      <button
        type="button"
        className="button-primary"
        data-testid="replay-play"
        disabled={!metrics}
        onClick={() => send({ type: playing ? 'pause' : 'play' })}
      >
        {playing ? 'Pause' : 'Play'}
      </button>
      <label htmlFor="replay-speed">Speed</label>
      <select
        id="replay-speed"
        data-testid="replay-speed"
        value={speed}
        disabled={!metrics}
        onChange={(e) => on_speed(Number(e.target.value))}
      >
        {speeds.map((s) => (
          <option key={s} value={s}>
            {s}×
          </option>
        ))}
      </select>
      <label htmlFor="replay-seek">Position</label>
      <input
        id="replay-seek"
        ref={seek_ref}
        data-testid="replay-seek"
        type="range"
        min={0}
        max={duration}
        step={0.1}
        value={Math.min(position, duration)}
        disabled={!metrics || duration <= 0}
        aria-valuetext={`${position.toFixed(1)} of ${duration.toFixed(1)} seconds`}
        onChange={(e) => {
          sent_at.current = 0;
          set_held(Number(e.target.value));
        }}
      />
      <span className="replay-time" aria-hidden="true">
        {position.toFixed(1)} / {duration.toFixed(1)} s
      </span>
      {seeking && (
        <span className="replay-seeking" role="status" data-testid="replay-seeking">
          <span className="spinner" aria-hidden="true" /> Seeking to {(metrics.seek_to_s ?? position).toFixed(1)} s…
        </span>
      )}
    </div>
  );
}
