import { useEffect, useRef, type RefObject } from 'react';
import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';

/** What a chart is drawn from, for the width it gets. */
export type ChartMaker = (width: number) => { options: uPlot.Options; data: uPlot.AlignedData };

/**
 * A uPlot chart inside the element `box` refers to: built by `make` whenever `deps` change (null:
 * no chart), kept at the element's width and `height`, destroyed when it is rebuilt or the
 * component goes. Returns a ref to the chart (null while there is none), e.g. to redraw it.
 */
export function useUplot(
  box: RefObject<HTMLDivElement | null>,
  make: ChartMaker | null,
  height: number,
  deps: readonly unknown[],
): RefObject<uPlot | null> {
  const plot = useRef<uPlot | null>(null);
  useEffect(() => {
    const element = box.current;
    if (!element || !make) return;
    const width_of = () => Math.max(Math.floor(element.clientWidth), 200);
    const { options, data } = make(width_of());
    const chart = new uPlot(options, data, element);
    plot.current = chart;
    const observer = new ResizeObserver(() => {
      const width = width_of();
      if (width !== chart.width) chart.setSize({ width, height });
    });
    observer.observe(element);
    return () => {
      observer.disconnect();
      chart.destroy();
      plot.current = null;
    };
    // The caller names what the chart depends on; `make` is a new function every render.
  }, deps); // eslint-disable-line react-hooks/exhaustive-deps
  return plot;
}
