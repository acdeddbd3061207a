import { describe, expect, it } from 'vitest';
import { calibration_job } from '../../test_support';
import {
  format_constant,
  format_decade,
  format_kpa,
  format_misfit,
  format_spread,
  parameter_label,
  progress_text,
  scene_file_name,
  spread_summary,
} from './tissue_format';

describe('progress_text', () => {
  it('says the step, the best misfit and the simulations used of the budget', () => {
    expect(progress_text(calibration_job({}))).toBe('iteration 12 · misfit 3.1e-4 · 480 of 2000 simulations');
  });

  it('counts generations for the population searches', () => {
    const job = calibration_job({ method: 'cmaes', budget: 500, progress: { iteration: 3, evaluations: 42, misfit: 0.5234 } });
    expect(progress_text(job)).toBe('generation 3 · misfit 0.52 · 42 of 500 simulations');
  });

  it('calls a per-node search’s number its objective: the smoothness prior is in it', () => {
    expect(progress_text(calibration_job({ per: 'node' }))).toBe('iteration 12 · objective 3.1e-4 · 480 of 2000 simulations');
  });

  it('says a queued job waits', () => {
    expect(progress_text(calibration_job({ status: 'queued', progress: null }))).toBe('waiting to start');
  });
});

describe('numbers', () => {
  it('shows moduli in kPa to three significant figures and nu as it is', () => {
    expect(format_kpa(12345)).toBe('12.3 kPa');
    expect(format_kpa(3000)).toBe('3.00 kPa');
    expect(format_kpa(2.46e-13)).toBe('2.46e-16 kPa');
    expect(format_constant('E[4]', 250)).toBe('0.250 kPa');
    expect(format_constant('nu[0]', 0.45)).toBe('0.45');
  });

  it('gives spreads in per cent of the value, to two figures', () => {
    expect(format_spread('E[0]', 79.2, 3600)).toBe('± 2.2 %');
    expect(format_spread('nu[0]', 0.012, 0.45)).toBe('± 2.7 %');
    expect(format_spread('E[0]', 18, 3600)).toBe('± 0.50 %');
    expect(format_spread('E[0]', -18, -3600)).toBe('± 0.50 %');
    expect(format_spread('E[0]', 2.46e-13, 3600)).toBe('± <0.001 %');
    // No per cent of nothing.
    expect(format_spread('E[0]', 500, 0)).toBe('± 0.500 kPa');
  });

  it('writes misfits short', () => {
    expect(format_misfit(0)).toBe('0');
    expect(format_misfit(3.14e-4)).toBe('3.1e-4');
    expect(format_misfit(1.5e3)).toBe('1.5e3');
  });

  it('labels a log10 axis by whole decades', () => {
    expect([-29, -3, -2, -1, 0, 1, 3].map(format_decade)).toEqual(['1e-29', '1e-3', '0.01', '0.1', '1', '10', '1e3']);
  });

  it('summarises node moduli by their smallest, median and largest', () => {
    expect(spread_summary([5, 1, 3])).toEqual({ min: 1, median: 3, max: 5 });
    expect(spread_summary([4, 1, 3, 2])).toEqual({ min: 1, median: 2.5, max: 4 });
  });
});

describe('names', () => {
  it('names a constant by its label or node', () => {
    const value = { name: 'E[0]', owner: 0, start: 1, value: 1, spread: 0 };
    expect(parameter_label(value, 'label')).toBe('E, label 0');
    expect(parameter_label({ ...value, name: 'nu[0]' }, 'label')).toBe('ν, label 0');
    expect(parameter_label({ ...value, name: 'E[17]', owner: 17 }, 'node')).toBe('E, node 17');
  });

  it('names a scene by its file', () => {
    expect(scene_file_name('scenes/calibration/cube.json')).toBe('cube.json');
    expect(scene_file_name('cube.json')).toBe('cube.json');
  });
});
