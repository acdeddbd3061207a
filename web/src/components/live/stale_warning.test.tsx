import { render, screen } from '@testing-library/react';
import { describe, expect, it } from 'vitest';
import type { StreamMetrics } from '../../stream';
import { stream_metrics } from '../../test_support';
import { StaleWarning } from './stale_warning';

const metrics = (change: Partial<StreamMetrics>) => stream_metrics({ sim_time_s: 4, steps: 2000, frames_sent: 100, ...change });

describe('StaleWarning', () => {
  it('says nothing while the picture moves and the simulation keeps time', () => {
    const { container } = render(<StaleWarning metrics={metrics({})} picture_age_s={0.1} />);
    expect(container.textContent).toBe('');
  });

  it('warns of a picture that stands still while the session runs, with the lag', () => {
    render(<StaleWarning metrics={metrics({ behind_real_time: true, lag_ms: 840, real_time_factor: 0.31 })} picture_age_s={15.4} />);
    const alert = screen.getByRole('alert');
    expect(alert.textContent).toContain('The picture has not changed for 15 s.');
    expect(alert.textContent).toContain('The simulation is 840 ms behind real time (0.31× real time).');
  });

  it('names a tool whose force model went stale at the station', () => {
    const link = {
      loop_hz: 1000,
      rtt_p50_ms: 2,
      rtt_p99_ms: 5,
      loss_down: 0,
      states_sent: 500,
      states_held: 0,
      devices: [
        { index: 0, model_age_ms: 3, fault: 'none', force_n: 1, damping_ns_m: 0, dissipated_j: 0 },
        { index: 1, model_age_ms: 412, fault: 'stale model', force_n: 0, damping_ns_m: 0, dissipated_j: 0 },
      ],
    };
    render(<StaleWarning metrics={metrics({ link })} picture_age_s={0.2} />);
    expect(screen.getByRole('alert').textContent).toBe('Tool 2 has a stale force model (412 ms old): the station renders no force for it.');
  });

  it('is silent while the session is paused: a still picture is then expected', () => {
    const { container } = render(<StaleWarning metrics={metrics({ state: 'paused' })} picture_age_s={60} />);
    expect(container.textContent).toBe('');
  });
});
