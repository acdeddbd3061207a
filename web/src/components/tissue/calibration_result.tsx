import { useState } from 'react';
import { api, type CalibrationJob, type CalibrationResult as Result } from '../../api';
import { format_date_time } from '../../time';
import { useResource } from '../../use_resource';
import { ErrorAlert } from '../common/alerts';
import { CalibratedValues } from './calibrated_values';
import { FitChart } from './fit_chart';
import { MaterialForm } from './material_form';
import { MisfitHistoryChart } from './misfit_history_chart';
import { format_misfit, method_labels, per_labels, progress_text, status_labels } from './tissue_format';

/**
 * The chosen job: its state while it runs (the jobs list polls it), and once ended its result
 * (GET /api/calibration/jobs/{id}): the fit per contact, the misfit's history, the constants, and
 * for a done job a form to save them as a material, or the material's name once saved. `on_saved`
 * reloads what a saved material changes.
 */
export function CalibrationResult({ job, on_saved }: { job: CalibrationJob; on_saved: () => void }) {
  return (
    <div data-testid="calibration-result" data-status={job.status}>
      <p>
        <span className={`badge badge-${job.status}`} data-testid="calibration-result-status">
          {status_labels[job.status]}
        </span>{' '}
        {`${method_labels[job.method]}, ${per_labels[job.per].toLowerCase()}, on ${job.data_name}` +
          ` (${job.contacts} contacts, ${job.samples} samples)`}
      </p>
      {(job.status === 'queued' || job.status === 'running') && <p role="status">{progress_text(job)}</p>}
      {job.status === 'failed' && <ErrorAlert message={`The calibration failed: ${job.error ?? 'no reason given'}`} />}
      {job.status === 'cancelled' && (
        <p>
          {`Cancelled ${format_date_time(job.finished_at)}` +
            (job.error && job.error !== 'cancelled' ? ` (${job.error})` : '') +
            '. What it found before it stopped is below, if anything; only a done calibration can be saved.'}
        </p>
      )}
      {(job.status === 'done' || job.status === 'cancelled') && <ResultLoader job={job} on_saved={on_saved} />}
    </div>
  );
}

/** The result of an ended job: a done one's, or the best a cancelled one found before it stopped. */
function ResultLoader({ job, on_saved }: { job: CalibrationJob; on_saved: () => void }) {
  const detail = useResource(['calibration', 'jobs', job.id], () => api.calibration_job(job.id));
  const result = detail.data?.result;
  return (
    <>
      <ErrorAlert message={detail.error && `Could not load the result: ${detail.error}`} />
      {!detail.data && detail.loading && (
        <p className="muted" role="status">
          Loading the result…
        </p>
      )}
      {detail.data && !result && job.status === 'done' && (
        <p className="empty">The server holds no result for this calibration.</p>
      )}
      {result && <ResultView job={job} result={result} on_saved={on_saved} />}
    </>
  );
}

const misfit_hint =
  "The data's relative misfit, Σ |u_sim − u_measured|² / Σ |u_measured|², with the scene's constants → " +
  'with the calibrated ones.';
const objective_hint = ' The search minimised it plus a smoothness prior: its progress and history show that objective.';

function ResultView({ job, result, on_saved }: { job: CalibrationJob; result: Result; on_saved: () => void }) {
  // The name just saved, until the reloaded job carries it.
  const [saved_name, set_saved_name] = useState<string | null>(null);
  const material = job.material ?? saved_name;
  const c = result.calibration;
  const step = job.method === 'lm' ? 'iteration' : 'generation';
  return (
    <>
      <dl className="calibration-summary" data-testid="calibration-summary">
        <div>
          <dt title={c.parameters === 'node' ? misfit_hint + objective_hint : misfit_hint}>Misfit</dt>
          <dd data-testid="calibration-misfit">{`${format_misfit(c.start_misfit)} → ${format_misfit(c.misfit)}`}</dd>
        </div>
        <div>
          <dt>Simulations</dt>
          <dd>{`${c.evaluations} (${c.iterations} ${step}s)`}</dd>
        </div>
        <div>
          <dt>Time</dt>
          <dd>{`${c.seconds.toFixed(1)} s`}</dd>
        </div>
        <div>
          <dt>Stopped</dt>
          <dd data-testid="calibration-stopped">{c.stopped}</dd>
        </div>
      </dl>
      <div className="calibration-charts">
        <FitChart fits={c.fits} />
        <MisfitHistoryChart
          history={c.history}
          start={c.parameters === 'label' ? c.start_misfit : null}
          step={step}
          objective={c.parameters === 'node'}
        />
      </div>
      <h3 id="calibration-values-title">Parameters</h3>
      <CalibratedValues values={c.values} per={c.parameters} node_moduli={result.node_moduli} />
      {job.status === 'done' &&
        (material ? (
          <p role="status" data-testid="calibration-saved-as">{`Saved as material “${material}”.`}</p>
        ) : (
          <>
            <h3>Save as material</h3>
            <MaterialForm
              job_id={job.id}
              on_saved={(name) => {
                set_saved_name(name);
                on_saved();
              }}
            />
          </>
        ))}
    </>
  );
}
