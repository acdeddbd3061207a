import { useEffect } from 'react';
import { api, type CalibrationJob } from '../../api';
import { format_date_time } from '../../time';
import { useFormAction } from '../../use_form_action';
import { useResource, type Resource } from '../../use_resource';
import { ErrorAlert } from '../common/alerts';
import { DataTable } from '../common/data_table';
import { is_active, method_labels, progress_parts, progress_text, scene_file_name, status_labels } from './tissue_format';

const poll_ms = 1000;

/**
 * The calibration jobs, newest first (GET /api/calibration/jobs), reloaded every second while any
 * of them is queued or running so that their progress moves; not at all once they all ended.
 */
export function useCalibrationJobs(): Resource<CalibrationJob[]> {
  const jobs = useResource(['calibration', 'jobs'], api.calibration_jobs);
  const { reload } = jobs;
  const active = jobs.data?.some(is_active) ?? false;
  useEffect(() => {
    if (!active) return;
    const timer = window.setInterval(reload, poll_ms);
    return () => window.clearInterval(timer);
  }, [active, reload]);
  return jobs;
}

/** The scene's title where the scenes list knows it, else its id. */
export function useSceneTitle(): (id: string) => string {
  const scenes = useResource(['calibration', 'scenes'], api.calibration_scenes);
  return (id) => scenes.data?.find((s) => s.id === id)?.title ?? id;
}

/**
 * The jobs as a table narrow enough for its card beside the form: the scene by its file name (its
 * title and who started a job in tooltips), the progress under the status, misfits kept whole.
 * "Show" selects one for the result panel, "Cancel" stops one that has not ended.
 */
export function CalibrationJobs({
  jobs,
  selected,
  on_select,
  on_changed,
}: {
  jobs: CalibrationJob[];
  selected: number | null;
  on_select: (id: number) => void;
  on_changed: () => void;
}) {
  const scene_title = useSceneTitle();
  const { busy, error, run } = useFormAction();

  async function cancel(job: CalibrationJob) {
    await run(async () => {
      await api.cancel_calibration(job.id);
      on_changed();
      return undefined;
    }, `Could not cancel calibration ${job.id}`);
  }

  return (
    <div className="calibration-jobs" data-testid="calibration-jobs">
      <ErrorAlert message={error} />
      <DataTable<CalibrationJob>
        labelled_by="calibration-jobs-title"
        rows={jobs}
        row_key={(j) => j.id}
        row_class={(j) => (j.id === selected ? 'row-selected' : undefined)}
        columns={[
          { header: 'Run', cell: (j) => `#${j.id}`, className: 'numeric nowrap' },
          { header: 'Scene', cell: (j) => <span title={scene_title(j.scene)}>{scene_file_name(j.scene)}</span> },
          { header: 'Method', cell: (j) => method_labels[j.method] },
          {
            header: 'Data file',
            className: 'file-column',
            cell: (j) => (
              <>
                <span className="file-name">{j.data_name}</span>{' '}
                <span className="muted cell-line">{`${j.contacts} contacts, ${j.samples} samples`}</span>
              </>
            ),
          },
          {
            header: 'Status',
            cell: (j) => (
              <>
                <span className={`badge badge-${j.status}`} data-testid={`calibration-job-${j.id}-status`}>
                  {status_labels[j.status]}
                </span>{' '}
                <span className="cell-line" data-testid={`calibration-job-${j.id}-progress`}>
                  {j.status === 'failed' && j.error ? j.error : <Progress job={j} />}
                </span>
              </>
            ),
          },
          {
            header: 'Created',
            cell: (j) => <span title={`Started by ${j.created_by}`}>{format_date_time(j.created_at)}</span>,
          },
          {
            header: 'Actions',
            className: 'actions',
            cell: (j) => (
              <div className="row-actions">
                <button
                  type="button"
                  className="button-quiet button-small"
                  aria-label={`Show calibration ${j.id}`}
                  aria-pressed={j.id === selected}
                  onClick={() => on_select(j.id)}
                >
                  Show
                </button>
                {is_active(j) && (
                  <button
                    type="button"
                    className="button-danger button-small"
                    aria-label={`Cancel calibration ${j.id}`}
                    disabled={busy}
                    onClick={() => cancel(j)}
                  >
                    Cancel
                  </button>
                )}
              </div>
            ),
          },
        ]}
      />
    </div>
  );
}

/** "iteration 12 · misfit 3.1e-4 · …": the misfit kept whole ("1.4e-29" would break at its hyphen). */
function Progress({ job }: { job: CalibrationJob }) {
  const p = progress_parts(job);
  if (!p) return progress_text(job);
  return (
    <>
      {`${p.step} · `}
      <span className="nowrap">{p.measure}</span>
      {` · ${p.count}`}
    </>
  );
}
