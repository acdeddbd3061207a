// The REST API of docs/api.md: its types and one fetch wrapper that turns every failure into an
// ApiError carrying the server's own message.
import { z } from 'zod';

// Each GET answer is parsed by its zod schema (`schemas` below), so that a server that changed a
// field the dashboard reads fails loudly, naming the endpoint and the field, instead of showing
// "undefined". Extra fields are dropped (the curriculum's definition, which is sent back, keeps
// them); the types are the schemas' (z.infer).

const role = z.enum(['trainee', 'instructor', 'admin']);
export type Role = z.infer<typeof role>;

const user = z.object({
  id: z.number(),
  username: z.string(),
  display_name: z.string(),
  role,
  /** Disabled by an admin: cannot log in. */
  disabled: z.boolean(),
  /** An admin reset the password: the server answers nothing else until the user chose a new one. */
  must_change_password: z.boolean(),
});
export type User = z.infer<typeof user>;

const station = z.object({
  id: z.number(),
  name: z.string(),
  location: z.string(),
  /** What it can run ("bench", "laparoscopy", "arthroscopy"; "" = not declared). */
  kind: z.string(),
  /** Retired by an admin: kept for its history, no longer booked, started or connected to. */
  retired: z.boolean(),
  online: z.boolean(),
});
export type Station = z.infer<typeof station>;

/** A metric as the whole dashboard shows it (GET /api/metrics; curriculum/metric_catalogue.h). */
const metric_info = z.object({
  key: z.string(),
  name: z.string(),
  /** The unit values and thresholds are stored in ("N", "m^2", "count", ""). */
  unit: z.string(),
  /** How people read it and enter thresholds: shown = value × display_scale, in display_unit. */
  display_unit: z.string(),
  display_scale: z.number(),
  decimals: z.number(),
  better: z.enum(['lower', 'higher', '']),
  definition: z.string(),
});
export type MetricInfo = z.infer<typeof metric_info>;

/** A task a station can run, with what locks it for the person asking (GET /api/stations/{id}/tasks). */
const station_task = z.object({
  key: z.string(),
  name: z.string(),
  module: z.string(),
  instructions: z.string(),
  /** Why it may not start yet ("" when it may). */
  locked_reason: z.string(),
});
export type StationTask = z.infer<typeof station_task>;

const booking = z.object({
  id: z.number(),
  station_id: z.number(),
  station_name: z.string(),
  user_id: z.number(),
  username: z.string(),
  starts_at: z.string(),
  ends_at: z.string(),
  /** 'completed': the session held in it ended, and the slot with it. */
  status: z.enum(['active', 'cancelled', 'completed']),
  created_at: z.string(),
  /** GET /api/bookings only: whether it lets its person start a session now (the server's rule). */
  covers_now: z.boolean().optional(),
});
export type Booking = z.infer<typeof booking>;

/** One active booking of a station as its calendar shows it (GET /api/stations/{id}/schedule). */
const schedule_entry = z.object({
  /** null for another person's booking seen by a trainee. */
  id: z.number().nullable(),
  starts_at: z.string(),
  ends_at: z.string(),
  mine: z.boolean(),
  /** Who booked it: for instructors and admins only. */
  username: z.string().nullable(),
});
export type ScheduleEntry = z.infer<typeof schedule_entry>;

const session = z.object({
  id: z.number(),
  trainee_id: z.number(),
  trainee: z.string(),
  /** null when the station has since been removed. */
  station_id: z.number().nullable(),
  station: z.string().nullable(),
  task: z.string(),
  state: z.enum(['created', 'running', 'paused', 'finished', 'aborted']),
  started_at: z.string().nullable(),
  ended_at: z.string().nullable(),
});
export type Session = z.infer<typeof session>;

const threshold = z.object({ op: z.enum(['<=', '>=']), value: z.number() });

const score = z.object({
  id: z.number(),
  session_id: z.number(),
  trainee: z.string(),
  task: z.string(),
  metric: z.string(),
  value: z.number(),
  unit: z.string(),
  passed: z.boolean(),
  created_at: z.string(),
  /** A completion criterion of the task rather than a metric's threshold. */
  criterion: z.boolean(),
  /** What it was judged against when stored (null: not known). */
  threshold: threshold.nullable(),
});
export type Score = z.infer<typeof score>;

/** What the server holds of a session that is still live (docs/api.md, "Live sessions"). */
const live_state = z.object({
  state: z.enum(['running', 'paused', 'finished']),
  /** Why the session is in this state, e.g. "station agent offline"; may be empty. */
  reason: z.string(),
  sim_time_s: z.number(),
  agent_online: z.boolean(),
  recording_id: z.number().nullable(),
});
export type LiveState = z.infer<typeof live_state>;

const live_session = session.extend({
  /** null once the server no longer holds the session. */
  live: live_state.nullable(),
  /** Whether it passed as an attempt (its scores, or the instructor's latest adjustment): the
   * server's verdict; null while it is not a finished, scored attempt. */
  passed: z.boolean().nullable(),
});
export type LiveSession = z.infer<typeof live_session>;

export type SessionAction = 'pause' | 'resume' | 'stop';

const recording = z.object({
  id: z.number(),
  session_id: z.number(),
  trainee: z.string(),
  task: z.string(),
  duration_s: z.number(),
  created_at: z.string(),
});
export type Recording = z.infer<typeof recording>;

// The curriculum's definition (curriculum/curriculum.h) goes back to the server when edited, so
// its objects keep the fields the dashboard does not read (looseObject).
const metric_requirement = z.looseObject({
  key: z.string(),
  threshold,
  unit: z.string(),
});
export type MetricRequirement = z.infer<typeof metric_requirement>;

const curriculum_task = z.looseObject({
  key: z.string(),
  name: z.string(),
  instructions: z.string(),
  /** The kind of station it needs ("" or absent: any). */
  station_kind: z.string().optional(),
  metrics: z.array(metric_requirement).optional(),
});
export type CurriculumTask = z.infer<typeof curriculum_task>;

/** A task of the curriculum as one trainee stands with it (GET /api/progress). */
const task_progress = z.object({
  key: z.string(),
  name: z.string(),
  module: z.string(),
  prerequisites: z.array(z.string()),
  attempts: z.number(),
  passed_attempts: z.number(),
  consecutive_passes: z.number(),
  required_passes: z.number(),
  mastered: z.boolean(),
  unlocked: z.boolean(),
  /** The prerequisites not yet mastered; empty when unlocked. */
  missing_prerequisites: z.array(z.string()),
  /** Why the task may not start ("task \"…\" is locked: master \"…\" first"), "" when it may. */
  locked_reason: z.string(),
});
export type TaskProgress = z.infer<typeof task_progress>;

const progress = z.object({
  trainee_id: z.number(),
  curriculum: z.string().nullable(),
  tasks: z.array(task_progress),
  /** The first unlocked task not yet mastered (null: all mastered). */
  next_task: z.string().nullable(),
});
export type Progress = z.infer<typeof progress>;

/** One trainee's progress with their name (GET /api/trainees/progress, for instructors). */
const trainee_progress = progress.extend({
  username: z.string(),
  display_name: z.string(),
});
export type TraineeProgress = z.infer<typeof trainee_progress>;

const curriculum_entry = z.object({
  id: z.number(),
  name: z.string(),
  definition: z.looseObject({
    name: z.string(),
    description: z.string(),
    modules: z.array(z.looseObject({ key: z.string(), name: z.string(), tasks: z.array(curriculum_task) })),
  }),
});
export type CurriculumEntry = z.infer<typeof curriculum_entry>;

/** An expert benchmark of one metric of one task (GET /api/benchmarks). */
const benchmark_stats = z.object({
  n: z.number(),
  mean: z.number(),
  sd: z.number(),
  median: z.number(),
  p10: z.number(),
  p90: z.number(),
});
export type BenchmarkStats = z.infer<typeof benchmark_stats>;

const benchmark = benchmark_stats.extend({
  task: z.string(),
  metric: z.string(),
  unit: z.string(),
});
export type Benchmark = z.infer<typeof benchmark>;

const event_kind = z.enum(['contact', 'grasp', 'release', 'cut', 'collision', 'never_event', 'target']);
export type EventKind = z.infer<typeof event_kind>;

const run_event = z.object({
  t_s: z.number(),
  kind: event_kind,
  /** 0: device 0 (right hand), 1: device 1 (left hand). */
  hand: z.number(),
  label: z.string(),
  /** Found in the recorded input, or seen by the simulation (a surgical scene's grasps, cuts...). */
  source: z.enum(['recording', 'simulation']),
});
export type RunEvent = z.infer<typeof run_event>;

/** One metric of an attempt against its threshold and the experts (GET /api/sessions/{id}/review). */
const review_result = z.object({
  metric: z.string(),
  value: z.number(),
  unit: z.string(),
  passed: z.boolean(),
  /** The threshold the score was judged against. */
  threshold: threshold.nullable(),
  /** The task's threshold today, when the curriculum changed it since the attempt. */
  threshold_now: threshold.nullable(),
  /** z: (value - mean) / sd, null without spread. */
  expert: benchmark_stats.extend({ z: z.number().nullable() }).nullable(),
});
export type ReviewResult = z.infer<typeof review_result>;

const review = z.object({
  session_id: z.number(),
  task: z.string(),
  trainee_id: z.number(),
  recording_id: z.number(),
  duration_s: z.number(),
  expert_run: z.boolean(),
  events: z.array(run_event),
  timeline: z.object({
    interval_s: z.number(),
    /** Bin starts; each hand's values and the cumulative damage per bin. */
    t_s: z.array(z.number()),
    hands: z.array(z.object({ peak_force_n: z.array(z.number()), speed_m_s: z.array(z.number()) })),
    damage_ns: z.array(z.number()),
  }),
  results: z.array(review_result),
  /** The simulation's damaged share of the tissue, sampled every interval_s; null before it was measured. */
  sim_damage: z.object({ interval_s: z.number(), values: z.array(z.number()) }).nullable(),
});
export type Review = z.infer<typeof review>;

const annotation = z.object({
  id: z.number(),
  session_id: z.number(),
  author: z.string(),
  t_s: z.number(),
  text: z.string(),
  created_at: z.string(),
});
export type Annotation = z.infer<typeof annotation>;

const score_adjustment = z.object({
  id: z.number(),
  session_id: z.number(),
  author: z.string(),
  passed: z.boolean(),
  reason: z.string(),
  created_at: z.string(),
});
export type ScoreAdjustment = z.infer<typeof score_adjustment>;

/** One entry of the audit log (GET /api/audit, admin): the latest 200, newest first. */
const audit_entry = z.object({
  id: z.number(),
  at: z.string(),
  /** null for a change no signed-in user made. */
  user_id: z.number().nullable(),
  /** e.g. "user.create", "station.calibrate", "curriculum.import", "export.scores". */
  action: z.string(),
  detail: z.string(),
  /** What the change changed, keyed by path ("kind", "modules/0/tasks/1/thresholds/0/max"): the
   * values before and after; null where there is none (a creation has no before). */
  before: z.record(z.string(), z.unknown()).nullable(),
  after: z.record(z.string(), z.unknown()).nullable(),
});
export type AuditEntry = z.infer<typeof audit_entry>;

/** A station's calibration (GET and PUT /api/stations/{id}/calibration; PUT takes the bare one). */
const calibration_answer = z.object({
  station_id: z.number(),
  /** True while the station has none stored: the calibration is then the server's default. */
  default: z.boolean(),
  calibration: z.unknown(),
});
export type CalibrationAnswer = z.infer<typeof calibration_answer>;

/** A user as admins list them: a trainee with the ids of the instructors who teach them. */
const listed_user = user.extend({ instructor_ids: z.array(z.number()).optional() });
export type ListedUser = z.infer<typeof listed_user>;

// Tissue calibration (docs/calibration.md): a scene's material constants fitted to a probe's
// force-displacement data by a job on the server, and the materials saved from finished jobs.
const calibration_method = z.enum(['ga', 'cmaes', 'lm']);
export type CalibrationMethod = z.infer<typeof calibration_method>;

/** What is fitted: E and nu per label of the scene's mesh, or a modulus per node (mass-spring). */
const calibration_per = z.enum(['label', 'node']);
export type CalibrationPer = z.infer<typeof calibration_per>;

/** A scene that can be calibrated (GET /api/calibration/scenes). */
const calibration_scene = z.object({
  /** Its path on the server, e.g. "scenes/calibration/cube.json". */
  id: z.string(),
  title: z.string(),
  /** The material model ("mss", "corotational", …). */
  model: z.string(),
  /** What may be fitted in it. */
  per: z.array(calibration_per),
  /** Whether GET /api/calibration/example?scene=<id> has a data file for it. */
  has_example: z.boolean(),
});
export type CalibrationScene = z.infer<typeof calibration_scene>;

const calibration_job = z.object({
  id: z.number(),
  scene: z.string(),
  method: calibration_method,
  per: calibration_per,
  /** The most simulations (evaluations of the misfit) the search may run. */
  budget: z.number(),
  data_name: z.string(),
  contacts: z.number(),
  samples: z.number(),
  status: z.enum(['queued', 'running', 'done', 'failed', 'cancelled']),
  /** After each generation (ga, cmaes) or iteration (lm); null before the first. The misfit is the best so far. */
  progress: z.object({ iteration: z.number(), evaluations: z.number(), misfit: z.number() }).nullable(),
  created_at: z.string(),
  created_by: z.string(),
  finished_at: z.string().nullable(),
  /** Why it failed. */
  error: z.string().nullable(),
  /** The name of the material saved from it. */
  material: z.string().nullable(),
});
export type CalibrationJob = z.infer<typeof calibration_job>;
export type CalibrationStatus = CalibrationJob['status'];

/** A material's constants: E [Pa], nu, density [kg/m^3], damping. */
const material_constants = z.object({ E: z.number(), nu: z.number(), density: z.number(), damping: z.number() });

/** One fitted constant: "E[0]" (Pa) or "nu[0]" of label 0, or "E[17]" of node 17 (per node). */
const calibrated_value = z.object({
  name: z.string(),
  /** Its label or node. */
  owner: z.number(),
  /** The scene's value. */
  start: z.number(),
  value: z.number(),
  /** The search's uncertainty of the value, in its unit. */
  spread: z.number(),
});
export type CalibratedValue = z.infer<typeof calibrated_value>;

/** One contact's displacement along the push [m] over time [s]: measured, and simulated with the
 * scene's constants (start) and the calibrated ones (fitted). */
const contact_fit = z.object({
  contact: z.number(),
  node: z.number(),
  /** From the probe's first position to the node it pushes [m]. */
  distance: z.number(),
  time: z.array(z.number()),
  force: z.array(z.number()),
  measured: z.array(z.number()),
  start: z.array(z.number()),
  fitted: z.array(z.number()),
});
export type ContactFit = z.infer<typeof contact_fit>;

const calibration_result = z.object({
  material: material_constants.extend({ model: z.string() }),
  /** Per label other than 0, by label. */
  materials: z.record(z.string(), material_constants).optional(),
  /** Per node [Pa], when fitted per node. */
  node_moduli: z.array(z.number()).optional(),
  calibration: z.object({
    method: z.string(),
    parameters: calibration_per,
    /** Relative: sum |u_sim - u_measured|^2 / sum |u_measured|^2. */
    misfit: z.number(),
    start_misfit: z.number(),
    evaluations: z.number(),
    iterations: z.number(),
    seconds: z.number(),
    /** Why the search stopped: "converged", "budget", "cancelled", … */
    stopped: z.string(),
    /** The best misfit after each generation or iteration. */
    history: z.array(z.number()),
    values: z.array(calibrated_value),
    fits: z.array(contact_fit),
  }),
});
export type CalibrationResult = z.infer<typeof calibration_result>;

/** A tissue material saved from a calibration; a task uses it by naming it in its curriculum. */
const material = material_constants.extend({
  id: z.number(),
  name: z.string(),
  scene: z.string(),
  model: z.string(),
  method: z.string(),
  misfit: z.number(),
  job: z.number().nullable(),
  created_at: z.string(),
  created_by: z.string(),
  /** The keys of the tasks whose curriculum names it. */
  tasks: z.array(z.string()),
});
export type Material = z.infer<typeof material>;

/** What POST /api/calibration/jobs takes: `data` is the CSV file's text. */
export interface CalibrationRequest {
  scene: string;
  method: CalibrationMethod;
  per: CalibrationPer;
  budget: number;
  data: string;
  data_name: string;
}

/** The schema of each GET endpoint's answer, for api below and for tests. */
export const schemas = {
  user,
  users: z.array(listed_user),
  stations: z.array(station),
  station_tasks: z.object({ station, tasks: z.array(station_task) }),
  bookings: z.array(booking),
  schedule: z.array(schedule_entry),
  calibration: calibration_answer,
  audit: z.array(audit_entry),
  sessions: z.array(session),
  live_session,
  recordings: z.array(recording),
  scores: z.array(score),
  curricula: z.array(curriculum_entry),
  metrics: z.array(metric_info),
  progress,
  progress_overview: z.array(trainee_progress),
  benchmarks: z.array(benchmark),
  review,
  annotations: z.array(annotation),
  adjustments: z.array(score_adjustment),
  calibration_scenes: z.object({ scenes: z.array(calibration_scene) }),
  calibration_jobs: z.object({ jobs: z.array(calibration_job) }),
  calibration_job: z.object({ job: calibration_job, result: calibration_result.nullable() }),
  materials: z.object({ materials: z.array(material) }),
};

export class ApiError extends Error {
  /** HTTP status, or 0 when the server could not be reached or its answer was not as expected. */
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

/** GET `path`, its answer parsed by `schema`; a mismatch is an ApiError naming the endpoint and field. */
async function get<T>(path: string, schema: z.ZodType<T>): Promise<T> {
  return parse_answer(`GET ${path}`, schema, await request<unknown>('GET', path));
}

/** `answer` as `schema` says, or an ApiError naming `endpoint` and the first field that does not fit. */
export function parse_answer<T>(endpoint: string, schema: z.ZodType<T>, answer: unknown): T {
  const parsed = schema.safeParse(answer);
  if (parsed.success) return parsed.data;
  const issue = parsed.error.issues[0];
  const where = issue ? field_path(issue.path) : 'the answer';
  const what = issue?.message ?? 'not as expected';
  throw new ApiError(
    0,
    `Unexpected answer from ${endpoint}: ${where}: ${what}. ` +
      'The dashboard and the server disagree; reload the page, and report it if it persists.',
  );
}

/** "[2].threshold.value" for a zod issue's path [2, "threshold", "value"]; "the answer" for []. */
function field_path(path: readonly PropertyKey[]): string {
  if (path.length === 0) return 'the answer';
  return path
    .map((part, i) => (typeof part === 'number' ? `[${part}]` : `${i === 0 ? '' : '.'}${String(part)}`))
    .join('');
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
  logout: () => request<undefined>('POST', '/api/logout'),
  me: () => get('/api/me', schemas.user),

  stations: () => get('/api/stations', schemas.stations),
  create_station: (name: string, location: string, kind: string) =>
    request<{ station: Station; token: string }>('POST', '/api/stations', { name, location, kind }),
  set_station_kind: (station_id: number, kind: string) =>
    request<Station>('PATCH', `/api/stations/${station_id}`, { kind }),
  update_station: (station_id: number, change: { kind?: string; retired?: boolean }) =>
    request<Station>('PATCH', `/api/stations/${station_id}`, change),
  station_tasks: (station_id: number) => get(`/api/stations/${station_id}/tasks`, schemas.station_tasks),

  bookings: () => get('/api/bookings', schemas.bookings),
  station_schedule: (station_id: number) => get(`/api/stations/${station_id}/schedule`, schemas.schedule),
  create_booking: (station_id: number, starts_at: string, ends_at: string) =>
    request<Booking>('POST', '/api/bookings', { station_id, starts_at, ends_at }),
  cancel_booking: (id: number) => request<undefined>('DELETE', `/api/bookings/${id}`),

  users: () => get('/api/users', schemas.users),
  set_instructors: (trainee_id: number, instructor_ids: number[]) =>
    request<ListedUser>('PUT', `/api/users/${trainee_id}/instructors`, { instructor_ids }),
  calibration: (station_id: number) => get(`/api/stations/${station_id}/calibration`, schemas.calibration),
  set_calibration: (station_id: number, calibration: unknown) =>
    request<CalibrationAnswer>('PUT', `/api/stations/${station_id}/calibration`, calibration),
  import_curriculum: (definition: unknown) => request<CurriculumEntry>('POST', '/api/curricula', definition),
  audit: () => get('/api/audit', schemas.audit),
  create_user: (user: { username: string; password: string; role: Role; display_name: string }) =>
    request<User>('POST', '/api/users', user),
  update_user: (user_id: number, change: { disabled: boolean }) =>
    request<ListedUser>('PATCH', `/api/users/${user_id}`, change),
  reset_password: (user_id: number, password: string) =>
    request<ListedUser>('POST', `/api/users/${user_id}/password`, { password }),
  change_password: (current_password: string, new_password: string) =>
    request<User>('POST', '/api/me/password', { current_password, new_password }),

  sessions: () => get('/api/sessions', schemas.sessions),
  session: (id: number) => get(`/api/sessions/${id}`, schemas.live_session),
  start_session: (station_id: number, task: string, expert = false) =>
    request<LiveSession>('POST', '/api/sessions', expert ? { station_id, task, expert } : { station_id, task }),
  session_action: (id: number, action: SessionAction) =>
    request<LiveSession>('POST', `/api/sessions/${id}/${action}`, {}),

  recordings: () => get('/api/recordings', schemas.recordings),
  scores: () => get('/api/scores', schemas.scores),
  curricula: () => get('/api/curricula', schemas.curricula),
  metrics: () => get('/api/metrics', schemas.metrics),
  progress: () => get('/api/progress', schemas.progress),
  trainee_progress: (trainee_id: number) => get(`/api/trainees/${trainee_id}/progress`, schemas.progress),
  progress_overview: () => get('/api/trainees/progress', schemas.progress_overview),
  benchmarks: () => get('/api/benchmarks', schemas.benchmarks),
  review: (session_id: number) => get(`/api/sessions/${session_id}/review`, schemas.review),
  set_expert_run: (session_id: number, expert: boolean) =>
    request<{ session_id: number; expert_run: boolean }>('PUT', `/api/sessions/${session_id}/expert`, { expert }),
  annotations: (session_id: number) => get(`/api/sessions/${session_id}/annotations`, schemas.annotations),
  add_annotation: (session_id: number, t_s: number, text: string) =>
    request<Annotation>('POST', `/api/sessions/${session_id}/annotations`, { t_s, text }),
  adjustments: (session_id: number) => get(`/api/sessions/${session_id}/adjustments`, schemas.adjustments),
  adjust_score: (session_id: number, passed: boolean, reason: string) =>
    request<ScoreAdjustment>('POST', `/api/sessions/${session_id}/adjustments`, { passed, reason }),
  update_curriculum: (id: number, definition: CurriculumEntry['definition']) =>
    request<CurriculumEntry>('PUT', `/api/curricula/${id}`, definition),

  calibration_scenes: async () => (await get('/api/calibration/scenes', schemas.calibration_scenes)).scenes,
  /** newest first */
  calibration_jobs: async () => (await get('/api/calibration/jobs', schemas.calibration_jobs)).jobs,
  /** The job with its result (null until it is done). */
  calibration_job: (id: number) => get(`/api/calibration/jobs/${id}`, schemas.calibration_job),
  start_calibration: async (job: CalibrationRequest) =>
    (await request<{ job: CalibrationJob }>('POST', '/api/calibration/jobs', job)).job,
  cancel_calibration: async (id: number) =>
    (await request<{ job: CalibrationJob }>('POST', `/api/calibration/jobs/${id}/cancel`, {})).job,
  materials: async () => (await get('/api/materials', schemas.materials)).materials,
  /** Saves a done job's calibrated material under `name` (409 when the name is taken). */
  save_material: async (job: number, name: string) =>
    (await request<{ material: Material }>('POST', '/api/materials', { job, name })).material,
};

/** The example data file of a scene (text/csv), for a download link. */
export function calibration_example_url(scene: string): string {
  return `/api/calibration/example?scene=${encodeURIComponent(scene)}`;
}
