// The metric catalogue (GET /api/metrics), fetched once per page load and shared by one query:
// every page names, scales and rounds a metric the same way, and thresholds are entered in the
// unit shown.
import { useQuery } from '@tanstack/react-query';
import { api, type MetricInfo } from './api';
import { format_value } from './components/common/format';

export type MetricCatalogue = Map<string, MetricInfo>;

function to_catalogue(list: MetricInfo[]): MetricCatalogue {
  return new Map(list.map((m) => [m.key, m]));
}

/** The catalogue, or null while it loads (or could not be loaded: then keys and raw units show). */
export function useMetricCatalogue(): MetricCatalogue | null {
  // The catalogue is the server's code, not its data: it never changes while the page is open.
  const query = useQuery({ queryKey: ['metrics'], queryFn: api.metrics, staleTime: Infinity, select: to_catalogue });
  return query.data ?? null;
}

/** "Peak force", or the key itself when the catalogue does not know it. */
export function metric_name(catalogue: MetricCatalogue | null, key: string): string {
  return catalogue?.get(key)?.name ?? key;
}

/** A value in its display unit: "60 mm²", "85 %", "1.23 N". */
export function format_metric(catalogue: MetricCatalogue | null, key: string, value: number, unit = ''): string {
  const info = catalogue?.get(key);
  if (!info) return format_value(value, unit);
  if (!Number.isFinite(value)) return '—';
  const shown = (value * info.display_scale).toFixed(info.decimals);
  return info.display_unit ? `${shown} ${info.display_unit}` : shown;
}

/** A stored value as typed in its display unit (rounded to hide binary noise: 6e-5 m² is 60 mm²). */
export function to_display(info: MetricInfo | undefined, value: number): number {
  return info ? Number((value * info.display_scale).toPrecision(12)) : value;
}

/** A typed display value back in the stored unit. */
export function from_display(info: MetricInfo | undefined, shown: number): number {
  return info ? Number((shown / info.display_scale).toPrecision(12)) : shown;
}
