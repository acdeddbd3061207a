// The REST API of docs/api.md: its types and one fetch wrapper that turns every failure into an
// ApiError carrying the server's own message.

export type Role = 'trainee' | 'instructor' | 'admin';

export interface User {
  id: number;
  username: string;
  display_name: string;
  role: Role;
}

export interface Station {
  id: number;
  name: string;
  location: string;
  /** What it can run ("bench", "laparoscopy", "arthroscopy"; "" = not declared). */
  kind: string;
  online: boolean;
}

/** A metric as the whole dashboard shows it (GET /api/metrics; curriculum/metric_catalogue.h). */
export interface MetricInfo {
  key: string;
  name: string;
  /** The unit values and thresholds are stored in ("N", "m^2", "count", ""). */
  unit: string;
  /** How people read it and enter thresholds: shown = value × display_scale, in display_unit. */
  display_unit: string;
  display_scale: number;
  decimals: number;
  better: 'lower' | 'higher' | '';
  definition: string;
}

/** A task a station can run, with what locks it for the person asking (GET /api/stations/{id}/tasks). */
export interface StationTask {
  key: string;
  name: string;
  module: string;
  instructions: string;
  /** Why it may not start yet ("" when it may). */
  locked_reason: string;
}

export interface Booking {
  id: number;
  station_id: number;
  station_name: string;
  user_id: number;
  username: string;
  starts_at: string;
  ends_at: string;
  /** 'completed': the session held in it ended, and the slot with it. */
  status: 'active' | 'cancelled' | 'completed';
  created_at: string;
}

/** One active booking of a station as its calendar shows it (GET /api/stations/{id}/schedule). */
export interface ScheduleEntry {
  /** null for another person's booking seen by a trainee. */
  id: number | null;
  starts_at: string;
  ends_at: string;
  mine: boolean;
  /** Who booked it: for instructors and admins only. */
  username: string | null;
}

export interface Session {
  id: number;
  trainee_id: number;
  trainee: string;
  /** null when the station has since been removed. */
  station_id: number | null;
  station: string | null;
  task: string;
  state: 'created' | 'running' | 'paused' | 'finished' | 'aborted';
  started_at: string | null;
  ended_at: string | null;
}

export interface Score {
  id: number;
  session_id: number;
  trainee: string;
  task: string;
  metric: string;
  value: number;
  unit: string;
  passed: boolean;
  created_at: string;
  /** A completion criterion of the task rather than a metric's threshold. */
  criterion: boolean;
  /** What it was judged against when stored (null: not known). */
  threshold: { op: '<=' | '>='; value: number } | null;
}

/** What the server holds of a session that is still live (docs/api.md, "Live sessions"). */
export interface LiveState {
  state: 'running' | 'paused' | 'finished';
  /** Why the session is in this state, e.g. "station agent offline"; may be empty. */
  reason: string;
  sim_time_s: number;
  agent_online: boolean;
  recording_id: number | null;
}

export interface LiveSession extends Session {
  /** null once the server no longer holds the session. */
  live: LiveState | null;
}

export type SessionAction = 'pause' | 'resume' | 'stop';

export interface Recording {
  id: number;
  session_id: number;
  trainee: string;
  task: string;
  duration_s: number;
  created_at: string;
}

/** The part of a curriculum's definition the dashboard shows (curriculum/curriculum.h). */
export interface MetricRequirement {
  key: string;
  threshold: { op: '<=' | '>='; value: number };
  unit: string;
}

export interface CurriculumTask {
  key: string;
  name: string;
  instructions: string;
  /** The kind of station it needs ("" or absent: any). */
  station_kind?: string;
  metrics?: MetricRequirement[];
}

/** A task of the curriculum as one trainee stands with it (GET /api/progress). */
export interface TaskProgress {
  key: string;
  name: string;
  module: string;
  prerequisites: string[];
  attempts: number;
  passed_attempts: number;
  consecutive_passes: number;
  required_passes: number;
  mastered: boolean;
  unlocked: boolean;
  /** The prerequisites not yet mastered; empty when unlocked. */
  missing_prerequisites: string[];
  /** Why the task may not start ("task \"…\" is locked: master \"…\" first"), "" when it may. */
  locked_reason: string;
}

export interface Progress {
  trainee_id: number;
  curriculum: string | null;
  tasks: TaskProgress[];
  /** The first unlocked task not yet mastered (null: all mastered). */
  next_task: string | null;
}

/** One trainee's progress with their name (GET /api/trainees/progress, for instructors). */
export interface TraineeProgress extends Progress {
  username: string;
  display_name: string;
}

export interface CurriculumEntry {
  id: number;
  name: string;
  definition: { name: string; description: string; modules: { key: string; name: string; tasks: CurriculumTask[] }[] };
}

/** An expert benchmark of one metric of one task (GET /api/benchmarks). */
export interface BenchmarkStats {
  n: number;
  mean: number;
  sd: number;
  median: number;
  p10: number;
  p90: number;
}

export interface Benchmark extends BenchmarkStats {
  task: string;
  metric: string;
  unit: string;
}

export type EventKind = 'contact' | 'grasp' | 'release' | 'cut' | 'collision' | 'never_event' | 'target';

export interface RunEvent {
  t_s: number;
  kind: EventKind;
  /** 0: device 0 (right hand), 1: device 1 (left hand). */
  hand: number;
  label: string;
  /** Found in the recorded input, or seen by the simulation (a surgical scene's grasps, cuts...). */
  source: 'recording' | 'simulation';
}

/** One metric of an attempt against its threshold and the experts (GET /api/sessions/{id}/review). */
export interface ReviewResult {
  metric: string;
  value: number;
  unit: string;
  passed: boolean;
  /** The threshold the score was judged against. */
  threshold: { op: '<=' | '>='; value: number } | null;
  /** The task's threshold today, when the curriculum changed it since the attempt. */
  threshold_now: { op: '<=' | '>='; value: number } | null;
  /** z: (value - mean) / sd, null without spread. */
  expert: (BenchmarkStats & { z: number | null }) | null;
}

export interface Review {
  session_id: number;
  task: string;
  trainee_id: number;
  recording_id: number;
  duration_s: number;
  expert_run: boolean;
  events: RunEvent[];
  timeline: {
    interval_s: number;
    /** Bin starts; each hand's values and the cumulative damage per bin. */
    t_s: number[];
    hands: { peak_force_n: number[]; speed_m_s: number[] }[];
    damage_ns: number[];
  };
  results: ReviewResult[];
  /** The simulation's damaged share of the tissue, sampled every interval_s; null before it was measured. */
  sim_damage: { interval_s: number; values: number[] } | null;
}

export interface Annotation {
  id: number;
  session_id: number;
  author: string;
  t_s: number;
  text: string;
  created_at: string;
}

export interface ScoreAdjustment {
  id: number;
  session_id: number;
  author: string;
  passed: boolean;
  reason: string;
  created_at: string;
}

/** One entry of the audit log (GET /api/audit, admin): the latest 200, newest first. */
export interface AuditEntry {
  id: number;
  at: string;
  /** null for a change no signed-in user made. */
  user_id: number | null;
  /** e.g. "user.create", "station.calibrate", "curriculum.import", "export.scores". */
  action: string;
  detail: string;
}

/** A station's calibration (GET and PUT /api/stations/{id}/calibration; PUT takes the bare one). */
export interface CalibrationAnswer {
  station_id: number;
  /** True while the station has none stored: the calibration is then the server's default. */
  default: boolean;
  calibration: unknown;
}

/** A user as admins list them: a trainee with the ids of the instructors who teach them. */
export type ListedUser = User & { instructor_ids?: number[] };

export class ApiError extends Error {
  /** HTTP status, or 0 when the server could not be reached. */
  readonly status: number;

  constructor(status: number, message: string) {
    super(message);
    this.name = 'ApiError';
    this.status = status;
  }
}

let on_unauthorized: () => void = () => {};

/** Called whenever the server answers 401 to anything but a login attempt. */
export function set_unauthorized_handler(handler: () => void): void {
  on_unauthorized = handler;
}

async function request<T>(method: string, path: string, body?: unknown): Promise<T> {
  const headers: Record<string, string> = { Accept: 'application/json' };
  // The server refuses state-changing requests without this header (its CSRF defence).
  if (method !== 'GET') headers['Content-Type'] = 'application/json';
  const init: RequestInit = { method, headers, credentials: 'same-origin' };
  if (body !== undefined) init.body = JSON.stringify(body);

  let response: Response;
  try {
    response = await fetch(path, init);
  } catch {
    throw new ApiError(0, 'Could not reach the Incise server. Check your connection and try again.');
  }

  if (!response.ok) {
    const message = await error_message(response);
    if (response.status === 401 && path !== '/api/login') on_unauthorized();
    throw new ApiError(response.status, message);
  }
  if (response.status === 204) return undefined as T;
  return (await response.json()) as T;
}

async function error_message(response: Response): Promise<string> {
  const fallback = `The server answered ${response.status} ${response.statusText}`.trim() + '.';
  try {
    const body: unknown = await response.json();
    if (body && typeof body === 'object' && 'error' in body && typeof body.error === 'string') {
      return body.error;
    }
  } catch {
    // Not JSON (e.g. a proxy's error page): the status line is all we have.
  }
  return fallback;
}

export const api = {
  login: (username: string, password: string) =>
    request<{ user: User }>('POST', '/api/login', { username, password }),
  logout: () => request<void>('POST', '/api/logout'),
  me: () => request<User>('GET', '/api/me'),

  stations: () => request<Station[]>('GET', '/api/stations'),
  create_station: (name: string, location: string, kind: string) =>
    request<{ station: Station; token: string }>('POST', '/api/stations', { name, location, kind }),
  set_station_kind: (station_id: number, kind: string) =>
    request<Station>('PATCH', `/api/stations/${station_id}`, { kind }),
  station_tasks: (station_id: number) =>
    request<{ station: Station; tasks: StationTask[] }>('GET', `/api/stations/${station_id}/tasks`),

  bookings: () => request<Booking[]>('GET', '/api/bookings'),
  station_schedule: (station_id: number) => request<ScheduleEntry[]>('GET', `/api/stations/${station_id}/schedule`),
  create_booking: (station_id: number, starts_at: string, ends_at: string) =>
    request<Booking>('POST', '/api/bookings', { station_id, starts_at, ends_at }),
  cancel_booking: (id: number) => request<void>('DELETE', `/api/bookings/${id}`),

  users: () => request<ListedUser[]>('GET', '/api/users'),
  set_instructors: (trainee_id: number, instructor_ids: number[]) =>
    request<ListedUser>('PUT', `/api/users/${trainee_id}/instructors`, { instructor_ids }),
  calibration: (station_id: number) => request<CalibrationAnswer>('GET', `/api/stations/${station_id}/calibration`),
  set_calibration: (station_id: number, calibration: unknown) =>
    request<CalibrationAnswer>('PUT', `/api/stations/${station_id}/calibration`, calibration),
  import_curriculum: (definition: unknown) => request<CurriculumEntry>('POST', '/api/curricula', definition),
  audit: () => request<AuditEntry[]>('GET', '/api/audit'),
  create_user: (user: { username: string; password: string; role: Role; display_name: string }) =>
    request<User>('POST', '/api/users', user),

  sessions: () => request<Session[]>('GET', '/api/sessions'),
  session: (id: number) => request<LiveSession>('GET', `/api/sessions/${id}`),
  start_session: (station_id: number, task: string) =>
    request<LiveSession>('POST', '/api/sessions', { station_id, task }),
  session_action: (id: number, action: SessionAction) =>
    request<LiveSession>('POST', `/api/sessions/${id}/${action}`, {}),

  recordings: () => request<Recording[]>('GET', '/api/recordings'),
  scores: () => request<Score[]>('GET', '/api/scores'),
  curricula: () => request<CurriculumEntry[]>('GET', '/api/curricula'),
  metrics: () => request<MetricInfo[]>('GET', '/api/metrics'),
  progress: () => request<Progress>('GET', '/api/progress'),
  trainee_progress: (trainee_id: number) => request<Progress>('GET', `/api/trainees/${trainee_id}/progress`),
  progress_overview: () => request<TraineeProgress[]>('GET', '/api/trainees/progress'),
  benchmarks: () => request<Benchmark[]>('GET', '/api/benchmarks'),
  review: (session_id: number) => request<Review>('GET', `/api/sessions/${session_id}/review`),
  set_expert_run: (session_id: number, expert: boolean) =>
    request<{ session_id: number; expert_run: boolean }>('PUT', `/api/sessions/${session_id}/expert`, { expert }),
  annotations: (session_id: number) => request<Annotation[]>('GET', `/api/sessions/${session_id}/annotations`),
  add_annotation: (session_id: number, t_s: number, text: string) =>
    request<Annotation>('POST', `/api/sessions/${session_id}/annotations`, { t_s, text }),
  adjustments: (session_id: number) => request<ScoreAdjustment[]>('GET', `/api/sessions/${session_id}/adjustments`),
  adjust_score: (session_id: number, passed: boolean, reason: string) =>
    request<ScoreAdjustment>('POST', `/api/sessions/${session_id}/adjustments`, { passed, reason }),
  update_curriculum: (id: number, definition: CurriculumEntry['definition']) =>
    request<CurriculumEntry>('PUT', `/api/curricula/${id}`, definition),
};
