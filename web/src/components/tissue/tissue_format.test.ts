import { describe, expect, it } from 'vitest';
import { calibration_job } from '../../test_support';
import { format_constant, format_kpa, format_misfit, progress_text, spread_summary } from './tissue_format';

describe('progress_text', () => {
  it('says the step, the best misfit and the simulations used of the budget', () => {
    expect(progress_text(calibration_job({}))).toBe('iteration 12 · misfit 3.1e-4 · 480 of 2000 simulations');
  });

  it('counts generations for the population searches', () => {
    const job = calibration_job({ method: 'cmaes', budget: 500, progress: { iteration: 3, evaluations: 42, misfit: 0.5234 } });
    expect(progress_text(job)).toBe('generation 3 · misfit 0.52 · 42 of 500 simulations');
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

  it('writes misfits short', () => {
    expect(format_misfit(0)).toBe('0');
    expect(format_misfit(3.14e-4)).toBe('3.1e-4');
    expect(format_misfit(1.5e3)).toBe('1.5e3');
  });

  it('summarises node moduli by their smallest, median and largest', () => {
    expect(spread_summary([5, 1, 3])).toEqual({ min: 1, median: 3, max: 5 });
    expect(spread_summary([4, 1, 3, 2])).toEqual({ min: 1, median: 2.5, max: 4 });
  });
});
