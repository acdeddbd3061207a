import { fireEvent, render, screen } from '@testing-library/react';
import userEvent from '@testing-library/user-event';
import { describe, expect, it, vi } from 'vitest';
import { seek_target, TimelineChart } from './timeline_chart';

// uPlot draws on a canvas, which jsdom has not: the chart itself is not under test here.
vi.mock('../../use_uplot', () => ({ useUplot: () => ({ current: null }) }));

function chart(position_s: number, on_seek: (t: number) => void) {
  return (
    <TimelineChart
      title="Force"
      unit="N"
      t_s={[0, 1, 2]}
      duration_s={30}
      series={[{ label: 'Right hand', values: [0, 1, 0], color: '#000' }]}
      events={[]}
      position_s={position_s}
      on_seek={on_seek}
      test_id="timeline-force"
    />
  );
}

describe('TimelineChart keyboard seek', () => {
  it('is a focusable slider that states the replay position', () => {
    render(chart(12.5, vi.fn()));
    const slider = screen.getByRole('slider', { name: 'Force: replay position' });
    expect(slider.tabIndex).toBe(0);
    expect(slider.getAttribute('aria-valuenow')).toBe('12.5');
    expect(slider.getAttribute('aria-valuemin')).toBe('0');
    expect(slider.getAttribute('aria-valuemax')).toBe('30');
  });

  it('seeks by a step with the arrows and to either end with Home and End', async () => {
    const on_seek = vi.fn();
    render(chart(10, on_seek));
    const user = userEvent.setup();
    await user.tab();
    expect(document.activeElement).toBe(screen.getByRole('slider'));

    await user.keyboard('{ArrowRight}');
    expect(on_seek).toHaveBeenLastCalledWith(11);
    await user.keyboard('{ArrowLeft}');
    expect(on_seek).toHaveBeenLastCalledWith(9);
    await user.keyboard('{Home}');
    expect(on_seek).toHaveBeenLastCalledWith(0);
    await user.keyboard('{End}');
    expect(on_seek).toHaveBeenLastCalledWith(30);
    await user.keyboard('{PageUp}');
    expect(on_seek).toHaveBeenLastCalledWith(20);
    expect(on_seek).toHaveBeenCalledTimes(5);
  });

  it('leaves other keys alone', () => {
    const on_seek = vi.fn();
    render(chart(10, on_seek));
    fireEvent.keyDown(screen.getByRole('slider'), { key: 'a' });
    fireEvent.keyDown(screen.getByRole('slider'), { key: 'Tab' });
    expect(on_seek).not.toHaveBeenCalled();
  });
});

describe('seek_target', () => {
  it('stays within the recording', () => {
    expect(seek_target('ArrowLeft', 0.4, 30)).toBe(0);
    expect(seek_target('ArrowRight', 29.5, 30)).toBe(30);
    expect(seek_target('PageDown', 5, 30)).toBe(0);
    expect(seek_target('Enter', 5, 30)).toBeNull();
  });
});

describe('TimelineChart without samples', () => {
  it('says so instead of drawing a chart over an empty range', () => {
    render(
      <TimelineChart
        title="Force"
        unit="N"
        t_s={[]}
        duration_s={95}
        series={[{ label: 'Right hand', values: [], color: '#000' }]}
        events={[]}
        position_s={0}
        on_seek={vi.fn()}
        test_id="timeline-force"
      />,
    );
    expect(screen.getByText('No samples were recorded.')).toBeDefined();
  });
});
