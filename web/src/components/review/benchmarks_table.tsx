import type { Benchmark } from '../../api';
import { format_metric, useMetricCatalogue, type MetricCatalogue } from '../../metrics';
import { DataTable } from '../common/data_table';
import { MetricLabel } from './scores_table';

/** "12.3 s ± 1.4 s"; a single run has no spread to show. */
function mean_and_sd(catalogue: MetricCatalogue | null, b: Benchmark): string {
  const mean = format_metric(catalogue, b.metric, b.mean, b.unit);
  return b.n < 2 ? mean : `${mean} ± ${format_metric(catalogue, b.metric, b.sd, b.unit)}`;
}

/**
 * The expert benchmarks (GET /api/benchmarks): per task and metric, the spread of the values that
 * attempts marked as expert runs scored, which an attempt's review compares against.
 */
export function BenchmarksTable({ benchmarks }: { benchmarks: Benchmark[] }) {
  const catalogue = useMetricCatalogue();
  const shown = (b: Benchmark, value: number) => format_metric(catalogue, b.metric, value, b.unit);
  return (
    <div data-testid="benchmarks-table">
      {benchmarks.length === 0 ? (
        <p className="empty">No expert runs yet. Mark an attempt as an expert run on its review page.</p>
      ) : (
        <>
          <span id="benchmarks-table-label" className="visually-hidden">
            Expert benchmarks
          </span>
          <DataTable<Benchmark>
            labelled_by="benchmarks-table-label"
            rows={benchmarks}
            row_key={(b) => `${b.task}/${b.metric}`}
            columns={[
              { header: 'Task', cell: (b) => b.task },
              { header: 'Metric', cell: (b) => <MetricLabel catalogue={catalogue} metric={b.metric} /> },
              { header: 'Runs', cell: (b) => b.n, className: 'numeric' },
              { header: 'Mean ± SD', cell: (b) => mean_and_sd(catalogue, b), className: 'numeric' },
              { header: 'Median', cell: (b) => shown(b, b.median), className: 'numeric' },
              { header: 'p10–p90', cell: (b) => `${shown(b, b.p10)} – ${shown(b, b.p90)}`, className: 'numeric' },
            ]}
          />
        </>
      )}
    </div>
  );
}
