import { describe, expect, it } from 'vitest';
import { format_metric, from_display, metric_name, to_display, type MetricCatalogue } from './metrics';
import { cut_area, peak_force } from './test_support';

const catalogue: MetricCatalogue = new Map([
  [cut_area.key, cut_area],
  [peak_force.key, peak_force],
]);

describe('to_display and from_display', () => {
  it('scale a stored value into the display unit without binary noise', () => {
    expect(to_display(cut_area, 6e-5)).toBe(60);
    expect(to_display(cut_area, 1.234e-6)).toBe(1.234);
  });

  it('are inverse to each other over several magnitudes', () => {
    for (const stored of [0, 6e-5, 1.5e-4, 3.3e-7, 0.012, 2]) {
      expect(from_display(cut_area, to_display(cut_area, stored))).toBe(stored);
    }
    for (const shown of [0, 60, 12.5, 0.001, 4000]) {
      expect(to_display(cut_area, from_display(cut_area, shown))).toBe(shown);
    }
  });

  it('leave a value alone for a metric the catalogue does not know', () => {
    expect(to_display(undefined, 6e-5)).toBe(6e-5);
    expect(from_display(undefined, 60)).toBe(60);
  });
});

describe('format_metric', () => {
  it('shows a catalogue metric in its display unit with its decimals', () => {
    expect(format_metric(catalogue, 'cut_area', 6e-5)).toBe('60 mm²');
    expect(format_metric(catalogue, 'peak_force', 1.2345)).toBe('1.23 N');
  });

  it('shows a dash for a value that is not a number', () => {
    expect(format_metric(catalogue, 'peak_force', Number.NaN)).toBe('—');
  });

  it('falls back on the stored unit without a catalogue', () => {
    expect(format_metric(null, 'cut_area', 6e-5, 'm^2')).toBe('60 mm²');
    expect(metric_name(null, 'cut_area')).toBe('cut_area');
    expect(metric_name(catalogue, 'cut_area')).toBe('Cut area');
  });
});
