import { render, screen } from '@testing-library/react';
import userEvent from '@testing-library/user-event';
import { describe, expect, it, vi } from 'vitest';
import type { StreamMetrics } from '../../stream';
import { stream_metrics } from '../../test_support';
import { ReplayControls } from './replay_controls';

// A replay's metrics: it opens paused, at 1x, not seeking.
const metrics = (change: Partial<StreamMetrics>) =>
  stream_metrics({ state: 'paused', agent_online: false, duration_s: 30, speed: 1, playing: false, seeking: false, ...change });

describe('ReplayControls', () => {
  it('offers Play for a replay that opens paused, and sends play', async () => {
    const send = vi.fn();
    render(<ReplayControls metrics={metrics({})} duration_s={30} send={send} />);
    await userEvent.click(screen.getByTestId('replay-play'));
    expect(screen.getByTestId('replay-play').textContent).toBe('Play');
    expect(send).toHaveBeenCalledWith({ type: 'play' });
  });

  it('says it is seeking, and where to, until the seek lands', () => {
    const send = vi.fn();
    const { rerender } = render(<ReplayControls metrics={metrics({ seeking: true, seek_to_s: 21.5, sim_time_s: 2 })} duration_s={30} send={send} />);
    expect(screen.getByTestId('replay-seeking').textContent).toContain('Seeking to 21.5 s…');
    expect(screen.getByTestId<HTMLInputElement>('replay-seek').value).toBe('21.5');
    rerender(<ReplayControls metrics={metrics({ seeking: false, sim_time_s: 21.5 })} duration_s={30} send={send} />);
    expect(screen.queryByTestId('replay-seeking')).toBeNull();
  });

  it('offers Pause while playing', () => {
    render(<ReplayControls metrics={metrics({ playing: true, state: 'running' })} duration_s={30} send={vi.fn()} />);
    expect(screen.getByTestId('replay-play').textContent).toBe('Pause');
  });
});
