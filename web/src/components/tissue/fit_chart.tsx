import { useRef, useState } from 'react';
import type uPlot from 'uplot';
import type { ContactFit } from '../../api';
import { useUplot, type ChartMaker } from '../../use_uplot';

const chart_height = 240;
const colors = { measured: '#1f2933', start: '#c98a00', fitted: '#0f5e66' };
const mm_per_m = 1000;

const to_mm = (values: number[]) => values.map((v) => v * mm_per_m);
const mm_text = (mm: number) => `${mm.toPrecision(3)} mm`;
const format_mm = (m: number) => mm_text(m * mm_per_m);
/** The legend's value of a plotted displacement [mm]; none away from the data. */
const legend_mm = (_: uPlot, mm: number | null) => (mm === null ? '—' : mm_text(mm));

/** The largest magnitude of `values` (0 for none), with its sign. */
function peak(values: number[]): number {
  return values.reduce((p, v) => (Math.abs(v) > Math.abs(p) ? v : p), 0);
}

/**
 * One contact's displacement along the push over time, in mm and s: the measured samples as
 * points, the scene's constants ("start", dashed) and the calibrated ones ("fitted"). A select
 * chooses the contact; the sentence under the chart gives the peaks for those who cannot see it.
 */
export function FitChart({ fits }: { fits: ContactFit[] }) {
  const [chosen, set_chosen] = useState<number | null>(null);
  const box = useRef<HTMLDivElement>(null);
  const fit = fits.find((f) => f.contact === chosen) ?? fits[0];

  const only_points = (stroke: string): Partial<uPlot.Series> => ({
    paths: () => null,
    points: { show: true, size: 5, width: 1, space: 0, stroke, fill: stroke },
  });
  const make: ChartMaker | null =
    !fit || fit.time.length === 0
      ? null
      : (width) => ({
          options: {
            width,
            height: chart_height,
            legend: { show: true },
            cursor: { drag: { x: false, y: false } },
            scales: { x: { time: false } },
            axes: [
              { label: 'time [s]', size: 36 },
              { label: 'displacement [mm]', size: 60 },
            ],
            series: [
              { label: 't [s]' },
              { label: 'measured', stroke: colors.measured, value: legend_mm, ...only_points(colors.measured) },
              { label: 'start', stroke: colors.start, width: 1.5, dash: [6, 4], value: legend_mm, points: { show: false } },
              { label: 'fitted', stroke: colors.fitted, width: 2, value: legend_mm, points: { show: false } },
            ],
          },
          data: [fit.time, to_mm(fit.measured), to_mm(fit.start), to_mm(fit.fitted)],
        });
  useUplot(box, make, chart_height, [fit]);

  if (!fit) return <p className="empty">No contact to show.</p>;
  return (
    <figure className="fit-chart" data-testid="calibration-fit">
      <figcaption>
        <label htmlFor="calibration-contact">Contact</label>{' '}
        <select id="calibration-contact" value={fit.contact} onChange={(e) => set_chosen(Number(e.target.value))}>
          {fits.map((f) => (
            <option key={f.contact} value={f.contact}>
              {`Contact ${f.contact} (node ${f.node}, ${format_mm(f.distance)} from the probe)`}
            </option>
          ))}
        </select>
      </figcaption>
      <div ref={box} className="fit-plot" aria-hidden="true" />
      <p className="hint" data-testid="calibration-fit-summary">
        {`Largest displacement: measured ${format_mm(peak(fit.measured))}, with the scene's constants ` +
          `${format_mm(peak(fit.start))}, calibrated ${format_mm(peak(fit.fitted))}.`}
      </p>
    </figure>
  );
}
