// The view WebSocket of docs/api.md ("View WebSocket"): a live session or a replay streams binary
// frames (a 16-byte little-endian header, then a JPEG) and JSON text messages; the viewer answers
// with small JSON messages, above all an ack per drawn frame.

export interface FrameHeader {
  /** Counts from 1 per socket. */
  frame: number;
  width: number;
  height: number;
  sim_time_s: number;
}

const header_bytes = 16;

/** Splits a binary message into its header and JPEG, or null when it is too short to be a frame. */
export function parse_frame(data: ArrayBuffer): { header: FrameHeader; jpeg: Blob } | null {
  if (data.byteLength <= header_bytes) return null;
  const view = new DataView(data);
  const header: FrameHeader = {
    frame: view.getUint32(0, true),
    width: view.getUint16(4, true),
    height: view.getUint16(6, true),
    sim_time_s: view.getFloat64(8, true),
  };
  return { header, jpeg: new Blob([data.slice(header_bytes)], { type: 'image/jpeg' }) };
}

/** One device of the station as the agent's haptic loop sees it. */
export interface DeviceLink {
  index: number;
  model_age_ms: number;
  /** The watchdog's reason the force is off, "none" while it renders. */
  fault: string;
  force_n: number;
  damping_ns_m: number;
  dissipated_j: number;
}

/** The station link over the last second, as the agent reports it plus the server's loss_up. */
export interface LinkReport {
  loop_hz: number;
  rtt_p50_ms: number;
  rtt_p99_ms: number;
  loss_down: number;
  loss_up?: number;
  states_sent: number;
  states_held: number;
  devices: DeviceLink[];
}

export interface StreamMetrics {
  state: 'running' | 'paused' | 'finished';
  reason: string;
  sim_time_s: number;
  agent_online: boolean;
  /** Tool tip position [m]. */
  tool: [number, number, number];
  force_n: number;
  peak_force_n: number;
  path_length_m: number;
  /** The simulation's damaged share of the tissue volume and the largest strain so far. */
  damage_index?: number;
  peak_strain?: number;
  /** Surgical scenes only: the area cut [m^2], its mean distance from the marked line [m], and
   * whether a protected structure was cut. */
  cut_area_m2?: number;
  cut_mean_distance_m?: number;
  never_event?: boolean;
  /** Surgical scenes only: how often the simulation pulled tissue left inside out back toward
   * its rest shape once no tool worked it (0 in a sound run). */
  inverted_tets_pulled?: number;
  contact: boolean;
  steps: number;
  sim_rate_hz: number;
  /** Live sessions: whether the simulation keeps up with the clock (the server decides), how far
   * behind schedule it is [ms], simulated over wall time, and what it sheds ("" for nothing). */
  behind_real_time?: boolean;
  lag_ms?: number;
  real_time_factor?: number;
  shed?: string;
  frames_sent: number;
  /** Whether this viewer may switch the picture to the camera outside the body (instructors and
   * admins; the server decides). */
  outside_view_allowed?: boolean;
  /** Tools in the scene: 2 for a two-handed task. */
  hands?: number;
  /** The second hand's tool (two-handed tasks only). */
  tool_2?: [number, number, number];
  force_2_n?: number;
  /** Live sessions: the station agent's latest link report (docs/api.md). */
  link?: LinkReport;
  /** Replays only. A replay opens paused; a seek shows `seeking` (and where it goes) until it lands. */
  duration_s?: number;
  speed?: number;
  playing?: boolean;
  position_s?: number;
  seeking?: boolean;
  seek_to_s?: number;
}

export type ServerMessage = ({ type: 'metrics' } & StreamMetrics) | { type: 'ended'; reason: string };

/** The server's text message, or null for one this dashboard does not know (a newer server). */
export function parse_server_message(text: string): ServerMessage | null {
  let value: unknown;
  try {
    value = JSON.parse(text);
  } catch {
    return null;
  }
  if (!value || typeof value !== 'object' || !('type' in value)) return null;
  if (value.type === 'metrics' && 'sim_time_s' in value && typeof value.sim_time_s === 'number') {
    return value as ServerMessage;
  }
  if (value.type === 'ended') {
    const reason = 'reason' in value && typeof value.reason === 'string' ? value.reason : '';
    return { type: 'ended', reason };
  }
  return null;
}

export type ClientMessage =
  | { type: 'ack'; frame: number }
  | { type: 'configure'; fps?: number; width?: number; height?: number; view?: 'scope' | 'outside' }
  | { type: 'play' }
  | { type: 'pause' }
  | { type: 'speed'; value: number }
  | { type: 'seek'; t: number };

export interface StreamOptions {
  fps: number;
  width: number;
  height: number;
}

/** ws:// or wss:// on the page's own origin, so the login cookie travels with the upgrade. */
export function stream_url(path: string, options: StreamOptions): string {
  const scheme = window.location.protocol === 'https:' ? 'wss:' : 'ws:';
  const query = new URLSearchParams({
    fps: String(options.fps),
    width: String(options.width),
    height: String(options.height),
  });
  return `${scheme}//${window.location.host}${path}?${query}`;
}
