import { useEffect, useRef, type KeyboardEvent } from 'react';
import type uPlot from 'uplot';
import type { EventKind, RunEvent } from '../../api';
import { useUplot, type ChartMaker } from '../../use_uplot';

const chart_height = 120;
/** How far an arrow key moves the replay [s]; Page Up/Down move ten times as far. */
export const seek_step_s = 1;

/** The colour of each kind of event, shared by the chart's marker lines and the event list. */
export const event_colors: Record<EventKind, string> = {
  contact: '#2f6fb3',
  grasp: '#7b4fb3',
  release: '#a58bd0',
  cut: '#b36b00',
  collision: '#c0392b',
  never_event: '#7f0000',
  target: '#2e8b57',
};

export interface TimelineSeries {
  label: string;
  values: number[];
  color: string;
}

/**
 * One signal of an attempt over time (e.g. force per hand) under the replay: a line per series,
 * a vertical line at each event in its kind's colour, and a cursor line at the replay's position.
 * A click on the plot seeks the replay to that time; so do the keys of a slider when the chart
 * has the focus (arrows: ±1 s, Page Up/Down: ±10 s, Home/End: start/end).
 */
export function TimelineChart({
  title,
  unit,
  t_s,
  duration_s,
  series,
  events,
  position_s,
  on_seek,
  test_id,
}: {
  title: string;
  unit: string;
  t_s: number[];
  /** The attempt's length [s]: the end a seek can reach. */
  duration_s: number;
  series: TimelineSeries[];
  events: RunEvent[];
  position_s: number;
  on_seek: (t_s: number) => void;
  test_id: string;
}) {
  const box = useRef<HTMLDivElement>(null);
  // The draw hook reads these, so that a new position redraws without rebuilding the chart.
  const position = useRef(position_s);
  const seek = useRef(on_seek);
  useEffect(() => {
    seek.current = on_seek;
  }, [on_seek]);

  // No samples (a recording without ticks): uPlot cannot lay out axes over an empty range.
  const empty = t_s.length === 0;
  const make: ChartMaker | null = empty ? null : (width) => {
    const draw_markers = (u: uPlot) => {
      const ctx = u.ctx;
      const top = u.bbox.top;
      const height = u.bbox.height;
      const line = (t: number, color: string, line_width: number) => {
        const x = u.valToPos(t, 'x', true);
        ctx.strokeStyle = color;
        ctx.lineWidth = line_width;
        ctx.beginPath();
        ctx.moveTo(x, top);
        ctx.lineTo(x, top + height);
        ctx.stroke();
      };
      ctx.save();
      for (const e of events) line(e.t_s, event_colors[e.kind], 1.5 * devicePixelRatio);
      line(position.current, '#111', 2 * devicePixelRatio);
      ctx.restore();
    };
    // A click on the plot seeks the replay to the time under the cursor.
    const listen_for_clicks = (u: uPlot) => {
      u.over.addEventListener('click', () => {
        const left = u.cursor.left;
        if (left === undefined || left < 0) return;
        seek.current(Math.max(0, u.posToVal(left, 'x')));
      });
    };
    return {
      options: {
        width,
        height: chart_height,
        legend: { show: true },
        cursor: { drag: { x: false, y: false } },
        scales: { x: { time: false } },
        axes: [
          { label: 'time [s]', size: 36 },
          { label: unit, size: 56 },
        ],
        series: [{ label: 't [s]' }, ...series.map((s) => ({ label: s.label, stroke: s.color, width: 1.5 }))],
        hooks: { draw: [draw_markers], ready: [listen_for_clicks] },
      },
      data: [t_s, ...series.map((s) => s.values)],
    };
  };
  const plot = useUplot(box, make, chart_height, [t_s, series, events, unit]);

  useEffect(() => {
    position.current = position_s;
    plot.current?.redraw(false, false);
  }, [position_s, plot]);

  function on_key_down(event: KeyboardEvent<HTMLDivElement>) {
    const target = seek_target(event.key, position_s, duration_s);
    if (target === null) return;
    event.preventDefault();
    on_seek(target);
  }

  return (
    <figure className="timeline-chart" data-testid={test_id}>
      <figcaption>{title}</figcaption>
      {empty && <p className="empty">No samples were recorded.</p>}
      <div
        ref={box}
        className="timeline-plot"
        tabIndex={0}
        role="slider"
        aria-label={`${title}: replay position`}
        aria-valuemin={0}
        aria-valuemax={duration_s}
        aria-valuenow={position_s}
        aria-valuetext={`${position_s.toFixed(1)} s of ${duration_s.toFixed(1)} s`}
        onKeyDown={on_key_down}
      />
    </figure>
  );
}

/** Where a key sends the replay from `position_s` (null: not a seeking key), within [0, duration_s]. */
export function seek_target(key: string, position_s: number, duration_s: number): number | null {
  const moves: Record<string, number> = {
    ArrowLeft: -seek_step_s,
    ArrowDown: -seek_step_s,
    ArrowRight: seek_step_s,
    ArrowUp: seek_step_s,
    PageDown: -10 * seek_step_s,
    PageUp: 10 * seek_step_s,
    Home: -Infinity,
    End: Infinity,
  };
  const move = moves[key];
  if (move === undefined) return null;
  return Math.min(duration_s, Math.max(0, position_s + move));
}
