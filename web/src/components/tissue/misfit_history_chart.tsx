import { useRef } from 'react';
import type uPlot from 'uplot';
import { useUplot, type ChartMaker } from '../../use_uplot';
import { format_misfit } from './tissue_format';

const chart_height = 140;

/**
 * The best misfit after each generation or iteration of the search (`step` names which), on a
 * log scale when every value is positive (a search's misfit falls by decades, down to 1e-29 for
 * noise-free data). The scale is drawn as log10 on a linear axis: uPlot's own log scale throws
 * ("Invalid array length") over that many decades.
 */
export function MisfitHistoryChart({ history, step }: { history: number[]; step: string }) {
  const box = useRef<HTMLDivElement>(null);
  const log = history.every((m) => m > 0);
  const make: ChartMaker | null =
    history.length === 0
      ? null
      : (width) => ({
          options: {
            width,
            height: chart_height,
            legend: { show: false },
            cursor: { drag: { x: false, y: false } },
            scales: { x: { time: false } },
            axes: [
              { label: step, size: 36 },
              {
                label: 'misfit',
                size: 60,
                values: (_: uPlot, splits: number[]) => splits.map((v) => format_misfit(log ? 10 ** v : v)),
              },
            ],
            series: [{}, { label: 'misfit', stroke: '#0f5e66', width: 1.5, points: { show: history.length < 40 } }],
          },
          data: [history.map((_, i) => i + 1), log ? history.map((m) => Math.log10(m)) : history],
        });
  useUplot(box, make, chart_height, [history, step]);

  return (
    <figure className="history-chart" data-testid="calibration-history">
      <figcaption>{`Misfit per ${step}${log ? ' (log scale)' : ''}`}</figcaption>
      {history.length === 0 ? (
        <p className="empty">The search recorded no {step}.</p>
      ) : (
        <div ref={box} className="history-plot" aria-hidden="true" />
      )}
    </figure>
  );
}
