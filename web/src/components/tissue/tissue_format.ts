// How tissue calibration shows its numbers: moduli in kPa to three significant figures, spreads in
// per cent of the value, relative misfits in short scientific notation, and a job's progress as one line.
import type { CalibratedValue, CalibrationJob, CalibrationMethod, CalibrationPer, CalibrationStatus } from '../../api';

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

/** A scene's file name, "cube.json" for "scenes/calibration/cube.json": short enough for a table. */
export function scene_file_name(id: string): string {
  return id.slice(id.lastIndexOf('/') + 1) || id;
}

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

const constant_symbols: Record<string, string> = { E: 'E', nu: 'ν' };

/** "E, label 0" for "E[0]" fitted per label, "E, node 17" for "E[17]" per node, "ν, label 0" for "nu[0]". */
export function parameter_label(value: CalibratedValue, per: CalibrationPer): string {
  const constant = value.name.replace(/\[\d+\]$/, '');
  return `${constant_symbols[constant] ?? constant}, ${per} ${value.owner}`;
}

const two_figures = new Intl.NumberFormat(undefined, { minimumSignificantDigits: 2, maximumSignificantDigits: 2 });
/** Below this many per cent a spread is shown as "± <0.001 %": a noise-free fit's is about 1e-14 %. */
const smallest_percent = 0.001;

/** "± 2.2 %": the spread relative to the value; in the value's unit when the value is 0. */
export function format_spread(name: string, spread: number, value: number): string {
  if (value === 0) return `± ${format_constant(name, spread)}`;
  const percent = (100 * Math.abs(spread)) / Math.abs(value);
  return percent < smallest_percent ? `± <${smallest_percent} %` : `± ${two_figures.format(percent)} %`;
}

/** "3.1e-4" for 0.00031, "0.52" for 0.5234: misfits are relative, small numbers. */
export function format_misfit(misfit: number): string {
  if (misfit === 0) return '0';
  const size = Math.abs(misfit);
  if (size >= 0.01 && size < 100) return String(Number(misfit.toPrecision(2)));
  return misfit.toExponential(1).replace('e+', 'e');
}

/** 10^k as "0.01", "1", "1e-29": a misfit axis's whole decades, small ones as decimals. */
export function format_decade(k: number): string {
  return Math.abs(k) <= 2 ? String(10 ** k) : `1e${k}`;
}

/** A job's progress: the step reached, the best misfit so far, the simulations spent of the budget. */
export interface ProgressParts {
  /** "iteration 12" (ga and cmaes count generations). */
  step: string;
  /** "misfit 3.1e-4"; per node "objective …", the search's number with the smoothness prior in it,
   * not the data's misfit the result reports. */
  measure: string;
  /** "480 of 2000 simulations". */
  count: string;
}

/** The parts of a job's progress; null before its first step. */
export function progress_parts(job: CalibrationJob): ProgressParts | null {
  const p = job.progress;
  if (!p) return null;
  return {
    step: `${job.method === 'lm' ? 'iteration' : 'generation'} ${p.iteration}`,
    measure: `${job.per === 'node' ? 'objective' : 'misfit'} ${format_misfit(p.misfit)}`,
    count: `${p.evaluations} of ${job.budget} simulations`,
  };
}

/** "iteration 12 · misfit 3.1e-4 · 480 of 2000 simulations", or what a job without progress does. */
export function progress_text(job: CalibrationJob): string {
  const p = progress_parts(job);
  if (!p) return job.status === 'queued' ? 'waiting to start' : '—';
  return `${p.step} · ${p.measure} · ${p.count}`;
}

/** The smallest, median and largest of `values` (not empty). */
export function spread_summary(values: readonly number[]): { min: number; median: number; max: number } {
  const sorted = [...values].sort((a, b) => a - b);
  const mid = Math.floor(sorted.length / 2);
  const at = (i: number) => sorted[i] ?? Number.NaN;
  const median = sorted.length % 2 === 1 ? at(mid) : (at(mid - 1) + at(mid)) / 2;
  return { min: at(0), median, max: at(sorted.length - 1) };
}
