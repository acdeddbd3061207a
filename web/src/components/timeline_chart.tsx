import { useEffect, useRef } from 'react';
import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';
import type { EventKind, RunEvent } from '../api';

/** The colour of each kind of event, shared by the chart's marker lines and the event list. */
export const event_colors: Record<EventKind, string> = {
  contact: '#2f6fb3',
  grasp: '#7b4fb3',
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
 * A click on the plot seeks the replay to that time.
 */
export function TimelineChart({
  title,
  unit,
  t_s,
  series,
  events,
  position_s,
  on_seek,
  test_id,
}: {
  title: string;
  unit: string;
  t_s: number[];
  series: TimelineSeries[];
  events: RunEvent[];
  position_s: number;
  on_seek: (t_s: number) => void;
  test_id: string;
}) {
  const box = useRef<HTMLDivElement>(null);
  const plot = useRef<uPlot | null>(null);
  // The draw hook reads these, so that a new position redraws without rebuilding the chart.
  const position = useRef(position_s);
  const seek = useRef(on_seek);
  seek.current = on_seek;

  useEffect(() => {
    const element = box.current;
    if (!element) return;
    const draw_markers = (u: uPlot) => {
      const ctx = u.ctx;
      const top = u.bbox.top;
      const height = u.bbox.height;
      const line = (t: number, color: string, width: number) => {
        const x = u.valToPos(t, 'x', true);
        ctx.strokeStyle = color;
        ctx.lineWidth = width;
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
    const options: uPlot.Options = {
      width: Math.max(element.clientWidth, 200),
      height: 120,
      legend: { show: true },
      cursor: { drag: { x: false, y: false } },
      scales: { x: { time: false } },
      axes: [
        { label: 'time [s]', size: 36 },
        { label: unit, size: 56 },
      ],
      series: [{ label: 't [s]' }, ...series.map((s) => ({ label: s.label, stroke: s.color, width: 1.5 }))],
      hooks: { draw: [draw_markers] },
    };
    const data: uPlot.AlignedData = [t_s, ...series.map((s) => s.values)];
    const u = new uPlot(options, data, element);
    plot.current = u;
    const on_click = () => {
      const left = u.cursor.left;
      if (left === undefined || left < 0) return;
      seek.current(Math.max(0, u.posToVal(left, 'x')));
    };
    u.over.addEventListener('click', on_click);
    const resize = new ResizeObserver(() => {
      const width = Math.max(element.clientWidth, 200);
      if (width !== u.width) u.setSize({ width, height: 120 });
    });
    resize.observe(element);
    return () => {
      resize.disconnect();
      u.over.removeEventListener('click', on_click);
      u.destroy();
      plot.current = null;
    };
  }, [t_s, series, events, unit]);

  useEffect(() => {
    position.current = position_s;
    plot.current?.redraw(false, false);
  }, [position_s]);

  return (
    <figure className="timeline-chart" data-testid={test_id}>
      <figcaption>{title}</figcaption>
      <div ref={box} />
    </figure>
  );
}
