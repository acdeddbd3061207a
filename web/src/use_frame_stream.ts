import { useCallback, useEffect, useRef, useState, type RefObject } from 'react';
import {
  parse_frame,
  parse_server_message,
  stream_url,
  type ClientMessage,
  type StreamMetrics,
  type StreamOptions,
} from './stream';

export interface FrameStream {
  /** The canvas the frames are drawn on; its data-frame and data-sim-time name the last one drawn. */
  canvas_ref: RefObject<HTMLCanvasElement | null>;
  phase: 'connecting' | 'open' | 'closed';
  metrics: StreamMetrics | null;
  /** Frames drawn per second, measured here over the last second; null until measured. */
  fps: number | null;
  /** Seconds since the picture last changed (since the socket opened before the first frame),
   * measured every second; null until measured. */
  picture_age_s: number | null;
  /** Frames whose JPEG the browser could not decode (acknowledged all the same). */
  bad_frames: number;
  /** The reason of the server's "ended" message once a live session has finished. */
  ended_reason: string | null;
  close: { code: number; reason: string } | null;
  /** Sends a control message while the socket is open; otherwise does nothing. */
  send: (message: ClientMessage) => void;
}

export const default_view: StreamOptions = { fps: 30, width: 640, height: 480 };

/**
 * Opens the view WebSocket at `path` (e.g. "/api/sessions/7/view") for as long as the component
 * lives and draws its frames on `canvas_ref`. No reconnect: a closed stream stays closed and says why.
 */
export function useFrameStream(path: string, options: StreamOptions = default_view): FrameStream {
  const canvas_ref = useRef<HTMLCanvasElement>(null);
  const socket_ref = useRef<WebSocket | null>(null);
  const [phase, set_phase] = useState<FrameStream['phase']>('connecting');
  const [metrics, set_metrics] = useState<StreamMetrics | null>(null);
  const [fps, set_fps] = useState<number | null>(null);
  const [picture_age_s, set_picture_age_s] = useState<number | null>(null);
  const [bad_frames, set_bad_frames] = useState(0);
  const [ended_reason, set_ended_reason] = useState<string | null>(null);
  const [close, set_close] = useState<FrameStream['close']>(null);
  const { fps: wanted_fps, width, height } = options;
  // A new socket (another path or view) starts from nothing: reset while rendering, before it opens.
  const connection = `${path} ${wanted_fps} ${width} ${height}`;
  const [shown_connection, set_shown_connection] = useState(connection);
  if (shown_connection !== connection) {
    set_shown_connection(connection);
    set_phase('connecting');
    set_metrics(null);
    set_fps(null);
    set_picture_age_s(null);
    set_bad_frames(0);
    set_ended_reason(null);
    set_close(null);
  }

  useEffect(() => {
    const socket = new WebSocket(stream_url(path, { fps: wanted_fps, width, height }));
    socket.binaryType = 'arraybuffer';
    socket_ref.current = socket;
    let alive = true;
    let last_drawn = 0;
    let drawn = 0;
    // Frames are decoded one after the other so that they are drawn and acknowledged in order;
    // the server sends at most two unacknowledged frames, so this chain stays short.
    let drawing = Promise.resolve();

    const canvas = canvas_ref.current;
    if (canvas) {
      canvas.dataset.frame = '0';
      canvas.dataset.simTime = '0';
    }

    let counted_at = performance.now();
    let counted = 0;
    let drawn_at = counted_at;
    const meter = window.setInterval(() => {
      const now = performance.now();
      set_fps(((drawn - counted) * 1000) / (now - counted_at));
      set_picture_age_s((now - drawn_at) / 1000);
      counted = drawn;
      counted_at = now;
    }, 1000);

    async function draw(data: ArrayBuffer) {
      const frame = parse_frame(data);
      if (!frame) {
        if (alive) set_bad_frames((n) => n + 1);
        return;
      }
      const { header } = frame;
      try {
        const bitmap = await createImageBitmap(frame.jpeg);
        const target = canvas_ref.current;
        // A frame older than the one on screen is only acknowledged.
        if (alive && target && header.frame > last_drawn) {
          if (target.width !== header.width || target.height !== header.height) {
            target.width = header.width;
            target.height = header.height;
          }
          target.getContext('2d')?.drawImage(bitmap, 0, 0, target.width, target.height);
          // Written on the element itself rather than through React state: a re-render per frame
          // would cost far more than the drawing.
          target.dataset.frame = String(header.frame);
          target.dataset.simTime = String(header.sim_time_s);
          last_drawn = header.frame;
          drawn += 1;
          drawn_at = performance.now();
        }
        bitmap.close();
      } catch {
        if (alive) set_bad_frames((n) => n + 1);
      } finally {
        // The server stops sending frames to a viewer that does not acknowledge them, so a frame
        // that failed to decode is acknowledged too.
        if (socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify({ type: 'ack', frame: header.frame }));
      }
    }

    socket.onopen = () => alive && set_phase('open');
    socket.onmessage = (event: MessageEvent<ArrayBuffer | string>) => {
      const data = event.data;
      if (typeof data !== 'string') {
        drawing = drawing.then(() => draw(data));
        return;
      }
      const message = parse_server_message(data);
      if (!alive || !message) return;
      if (message.type === 'metrics') {
        set_metrics(message);
      } else {
        set_ended_reason(message.reason);
        // No metrics follow "ended"; the last ones may still say running or paused.
        set_metrics((last) => last && { ...last, state: 'finished', reason: message.reason });
      }
    };
    socket.onclose = (event) => {
      if (!alive) return;
      window.clearInterval(meter);
      set_fps(null);
      set_phase('closed');
      set_close({ code: event.code, reason: event.reason });
    };

    return () => {
      alive = false;
      window.clearInterval(meter);
      socket_ref.current = null;
      socket.close(1000, 'viewer left');
    };
  }, [path, wanted_fps, width, height]);

  const send = useCallback((message: ClientMessage) => {
    const socket = socket_ref.current;
    if (socket?.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
  }, []);

  return { canvas_ref, phase, metrics, fps, picture_age_s, bad_frames, ended_reason, close, send };
}
