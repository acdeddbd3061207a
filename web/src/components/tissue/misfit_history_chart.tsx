import { useRef } from 'react';
import type uPlot from 'uplot';
import { useUplot, type ChartMaker } from '../../use_uplot';
import { format_decade, format_misfit } from './tissue_format';

const chart_height = 140;
/** Tick steps for counts of steps, and for decades on the log10 axis: whole numbers only. */
const whole_increments = [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000];

/** The log10 scale's range out to whole decades, at least one: ticks then fall inside it. */
function decade_range(_: uPlot, min: number, max: number): uPlot.Range.MinMax {
  const low = Math.floor(min);
  return [low, Math.max(Math.ceil(max), low + 1)];
}

/**
 * The best misfit after each generation or iteration of the search (`step` names which), from
 * `start` at step 0 when given, on a log scale when every value is positive (a search's misfit
 * falls by decades, down to 1e-29 for noise-free data). The scale is drawn as log10 on a linear
 * axis, ticked at whole decades: uPlot's own log scale throws ("Invalid array length") over that
 * many decades. `objective`: the values are the search's objective (per node, the smoothness prior
 * included), not the data's misfit alone.
 */
export function MisfitHistoryChart({
  history,
  start,
  step,
  objective,
}: {
  history: number[];
  start: number | null;
  step: string;
  objective: boolean;
}) {
  const box = useRef<HTMLDivElement>(null);
  const values = start === null ? history : [start, ...history];
  const first_step = start === null ? 1 : 0;
  const log = values.every((m) => m > 0);
  const what = objective ? 'objective' : 'misfit';
  const make: ChartMaker | null =
    history.length === 0
      ? null
      : (width) => ({
          options: {
            width,
            height: chart_height,
            legend: { show: false },
            cursor: { drag: { x: false, y: false } },
            scales: {
              x: { time: false },
              y: log ? { range: decade_range } : {},
            },
            axes: [
              { label: step, size: 36, incrs: whole_increments },
              log
                ? {
                    label: what,
                    size: 60,
                    incrs: whole_increments,
                    values: (_: uPlot, splits: number[]) => splits.map(format_decade),
                  }
                : {
                    label: what,
                    size: 60,
                    values: (_: uPlot, splits: number[]) => splits.map(format_misfit),
                  },
            ],
            series: [{}, { label: what, stroke: '#0f5e66', width: 1.5, points: { show: values.length < 40 } }],
          },
          data: [values.map((_, i) => i + first_step), log ? values.map((m) => Math.log10(m)) : values],
        });
  useUplot(box, make, chart_height, [history, start, step, objective]);

  const title = objective ? 'Objective' : 'Misfit';
  return (
    <figure className="history-chart" data-testid="calibration-history">
      <figcaption>{`${title} per ${step}${log ? ' (log scale)' : ''}`}</figcaption>
      {history.length === 0 ? (
        <p className="empty">The search recorded no {step}.</p>
      ) : (
        <div ref={box} className="history-plot" aria-hidden="true" />
      )}
    </figure>
  );
}
