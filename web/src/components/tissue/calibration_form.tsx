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
import { method_labels, per_labels } from './tissue_format';

const default_budget = 2000;
const max_budget = 20000;
const methods = Object.keys(method_labels) as CalibrationMethod[];

/**
 * Starts a calibration job (POST /api/calibration/jobs): a scene, a search, what to fit and a
 * budget of simulations, with a force-displacement CSV file whose text goes to the server as it
 * is. The server checks the file and names the line or contact of the first problem.
 */
export function CalibrationForm({ on_created }: { on_created: (job: CalibrationJob) => void }) {
  const scenes = useResource(['calibration', 'scenes'], api.calibration_scenes);
  return (
    <ResourceView resource={scenes} what="calibration scenes" empty="The server offers no scene to calibrate.">
      {(data) => <StartForm scenes={data} on_created={on_created} />}
    </ResourceView>
  );
}

function StartForm({ scenes, on_created }: { scenes: CalibrationScene[]; on_created: (job: CalibrationJob) => void }) {
  const [scene_id, set_scene_id] = useState('');
  const [method, set_method] = useState<CalibrationMethod>('lm');
  const [chosen_per, set_per] = useState<CalibrationPer>('label');
  const [budget, set_budget] = useState(String(default_budget));
  const [file, set_file] = useState<File | null>(null);
  // Changed after a start to give a fresh, empty file input.
  const [input_generation, set_input_generation] = useState(0);
  const { busy, error, status, run, clear } = useFormAction();

  // The chosen scene, or the first one until one is chosen; what it offers to fit, the chosen first.
  const scene = scenes.find((s) => s.id === scene_id) ?? scenes[0];
  const offered = scene?.per ?? [];
  const per = offered.includes(chosen_per) ? chosen_per : offered[0];

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    if (!scene || !per || !file) return;
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
        disabled={busy}
        onChange={(e) => {
          set_scene_id(e.target.value);
          clear();
        }}
      >
        {scenes.map((s) => (
          <option key={s.id} value={s.id}>
            {s.title}
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
