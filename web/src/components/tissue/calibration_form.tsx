import { useState, type SubmitEvent } from 'react';
import {
  api,
  calibration_example_url,
  type CalibrationJob,
  type CalibrationMethod,
  type CalibrationPer,
  type CalibrationScene,
} from '../../api';
import { InputError, useFormAction } from '../../use_form_action';
import { useResource } from '../../use_resource';
import { ErrorAlert, StatusMessage } from '../common/alerts';
import { ResourceView } from '../common/resource_view';
import { is_active, method_labels, per_labels, scene_file_name } from './tissue_format';

const default_budget = 2000;
const max_budget = 20000;
const methods = Object.keys(method_labels) as CalibrationMethod[];

/**
 * Starts a calibration job (POST /api/calibration/jobs): a scene, a search, what to fit and a
 * budget of simulations, with a force-displacement CSV file whose text goes to the server as it
 * is. The server checks the file and names the line or contact of the first problem.
 */
export function CalibrationForm({
  on_created,
  shown_job,
}: {
  on_created: (job: CalibrationJob) => void;
  /** The job the page shows, once listed: "Calibration N queued." lasts while it is N and has not ended. */
  shown_job: CalibrationJob | undefined;
}) {
  const scenes = useResource(['calibration', 'scenes'], api.calibration_scenes);
  return (
    <ResourceView resource={scenes} what="calibration scenes" empty="The server offers no scene to calibrate.">
      {(data) => <StartForm scenes={data} on_created={on_created} shown_job={shown_job} />}
    </ResourceView>
  );
}

/** "cube.json (mss)": short enough for the select; the full path when two scenes share a file name. */
function scene_option_label(scene: CalibrationScene, scenes: CalibrationScene[]): string {
  const name = scene_file_name(scene.id);
  const shared = scenes.some((s) => s !== scene && scene_file_name(s.id) === name);
  return `${shared ? scene.id : name} (${scene.model})`;
}

function StartForm({
  scenes,
  on_created,
  shown_job,
}: {
  scenes: CalibrationScene[];
  on_created: (job: CalibrationJob) => void;
  shown_job: CalibrationJob | undefined;
}) {
  const [scene_id, set_scene_id] = useState('');
  const [method, set_method] = useState<CalibrationMethod>('lm');
  const [chosen_per, set_per] = useState<CalibrationPer>('label');
  const [budget, set_budget] = useState(String(default_budget));
  const [file, set_file] = useState<File | null>(null);
  // Changed after a start to give a fresh, empty file input.
  const [input_generation, set_input_generation] = useState(0);
  const { busy, error, status, run, clear } = useFormAction();
  // The job "Calibration N queued." reports. The message goes once the page shows another job or
  // that one ended (no news until the list has it).
  const [queued_id, set_queued_id] = useState<number | null>(null);
  if (queued_id !== null && shown_job && (shown_job.id !== queued_id || !is_active(shown_job))) {
    set_queued_id(null);
    clear();
  }

  // The chosen scene, or the first one until one is chosen; what it offers to fit, the chosen first.
  const scene = scenes.find((s) => s.id === scene_id) ?? scenes[0];
  const offered = scene?.per ?? [];
  const per = offered.includes(chosen_per) ? chosen_per : offered[0];

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    if (!scene || !per || !file) return;
    set_queued_id(null);
    await run(async () => {
      const budget_value = Number(budget);
      if (!Number.isInteger(budget_value) || budget_value < 1 || budget_value > max_budget) {
        throw new InputError(`The budget must be a whole number of simulations from 1 to ${max_budget}.`);
      }
      // An editor's byte-order mark is not part of the data.
      const data = (await file.text()).replace(/^\uFEFF/, '');
      const job = await api.start_calibration({
        scene: scene.id,
        method,
        per,
        budget: budget_value,
        data,
        data_name: file.name,
      });
      set_file(null);
      set_input_generation((g) => g + 1);
      set_queued_id(job.id);
      on_created(job);
      return `Calibration ${job.id} queued.`;
    }, 'Could not start the calibration');
  }

  return (
    <form className="form" data-testid="calibration-form" aria-label="New calibration" onSubmit={on_submit}>
      <label htmlFor="calibration-scene">Scene</label>
      <select
        id="calibration-scene"
        value={scene?.id ?? ''}
        title={scene?.title}
        disabled={busy}
        onChange={(e) => {
          set_scene_id(e.target.value);
          clear();
        }}
      >
        {scenes.map((s) => (
          <option key={s.id} value={s.id} title={s.title}>
            {scene_option_label(s, scenes)}
          </option>
        ))}
      </select>
      {scene?.has_example && (
        <p className="hint">
          <a href={calibration_example_url(scene.id)} download data-testid="calibration-example">
            Example data
          </a>{' '}
          for this scene (CSV).
        </p>
      )}
      <div className="form-row">
        <div>
          <label htmlFor="calibration-method">Method</label>
          <select
            id="calibration-method"
            value={method}
            disabled={busy}
            onChange={(e) => set_method(e.target.value as CalibrationMethod)}
          >
            {methods.map((m) => (
              <option key={m} value={m}>
                {method_labels[m]}
              </option>
            ))}
          </select>
        </div>
        <div>
          <label htmlFor="calibration-per">Parameters</label>
          <select
            id="calibration-per"
            value={per ?? ''}
            disabled={busy}
            onChange={(e) => set_per(e.target.value as CalibrationPer)}
          >
            {offered.map((p) => (
              <option key={p} value={p}>
                {per_labels[p]}
              </option>
            ))}
          </select>
        </div>
        <div>
          <label htmlFor="calibration-budget">Budget (simulations)</label>
          <input
            id="calibration-budget"
            type="number"
            min={1}
            max={max_budget}
            step={1}
            required
            value={budget}
            disabled={busy}
            onChange={(e) => set_budget(e.target.value)}
          />
        </div>
      </div>
      <label htmlFor="calibration-data">Data file (CSV)</label>
      <input
        key={input_generation}
        id="calibration-data"
        type="file"
        accept=".csv,text/csv"
        // Not `required`: the button waits for a file, and jsdom's tests cannot satisfy the constraint.
        aria-required="true"
        disabled={busy}
        aria-describedby="calibration-data-hint"
        onChange={(e) => {
          set_file(e.target.files?.[0] ?? null);
          clear();
        }}
      />
      <p className="hint" id="calibration-data-hint">
        {file ? (
          <>
            Chosen: <span data-testid="calibration-data-name">{file.name}</span>.{' '}
          </>
        ) : null}
        One row per sample with the columns time_s, contact, x, y, z, dir_x, dir_y, dir_z and force_n (SI units).
      </p>
      <ErrorAlert message={error} />
      <StatusMessage message={status} />
      <button type="submit" className="button-primary" disabled={busy || !file || !scene || !per}>
        {busy ? 'Starting…' : 'Run calibration'}
      </button>
    </form>
  );
}
