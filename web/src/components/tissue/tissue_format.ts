// How tissue calibration shows its numbers: moduli in kPa to three significant figures, relative
// misfits in short scientific notation, and a job's progress as one line.
import type { CalibrationJob, CalibrationMethod, CalibrationPer, CalibrationStatus } from '../../api';

export const method_labels: Record<CalibrationMethod, string> = {
  ga: 'Genetic algorithm (seed 004)',
  cmaes: 'CMA-ES',
  lm: 'Levenberg-Marquardt',
};

/** A method's label when the name is one of ours (a material records the name as a string). */
export function method_label(name: string): string {
  const labels: Record<string, string> = method_labels;
  return labels[name] ?? name;
}

export const per_labels: Record<CalibrationPer, string> = {
  label: 'Per label',
  node: 'Per node (mass-spring)',
};

export const status_labels: Record<CalibrationStatus, string> = {
  queued: 'Queued',
  running: 'Running',
  done: 'Done',
  failed: 'Failed',
  cancelled: 'Cancelled',
};

/** Still to finish: its list and progress are polled. */
export function is_active(job: CalibrationJob): boolean {
  return job.status === 'queued' || job.status === 'running';
}

const three_figures = new Intl.NumberFormat(undefined, { minimumSignificantDigits: 3, maximumSignificantDigits: 3 });
const plain = new Intl.NumberFormat(undefined, { maximumSignificantDigits: 3 });

/** "12.3 kPa" for 12345 Pa; "2.46e-16 kPa" for a spread too small for decimals. */
export function format_kpa(pa: number): string {
  const kpa = pa / 1000;
  if (kpa !== 0 && Math.abs(kpa) < 0.001) return `${kpa.toExponential(2)} kPa`;
  return `${three_figures.format(kpa)} kPa`;
}

/** A fitted constant in its unit: E (Pa) in kPa, others (nu) as they are. */
export function format_constant(name: string, value: number): string {
  return name.startsWith('E') ? format_kpa(value) : plain.format(value);
}

/** "3.1e-4" for 0.00031, "0.52" for 0.5234: misfits are relative, small numbers. */
export function format_misfit(misfit: number): string {
  if (misfit === 0) return '0';
  const size = Math.abs(misfit);
  if (size >= 0.01 && size < 100) return String(Number(misfit.toPrecision(2)));
  return misfit.toExponential(1).replace('e+', 'e');
}

/** "iteration 12 · misfit 3.1e-4 · 480 of 2000 simulations" (ga and cmaes count generations). */
export function progress_text(job: CalibrationJob): string {
  const p = job.progress;
  if (!p) return job.status === 'queued' ? 'waiting to start' : '—';
  const step = job.method === 'lm' ? 'iteration' : 'generation';
  return `${step} ${p.iteration} · misfit ${format_misfit(p.misfit)} · ${p.evaluations} of ${job.budget} simulations`;
}

/** The smallest, median and largest of `values` (not empty). */
export function spread_summary(values: readonly number[]): { min: number; median: number; max: number } {
  const sorted = [...values].sort((a, b) => a - b);
  const mid = Math.floor(sorted.length / 2);
  const at = (i: number) => sorted[i] ?? Number.NaN;
  const median = sorted.length % 2 === 1 ? at(mid) : (at(mid - 1) + at(mid)) / 2;
  return { min: at(0), median, max: at(sorted.length - 1) };
}
