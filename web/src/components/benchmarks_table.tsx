import type { Benchmark } from '../api';
import { DataTable } from './data_table';
import { format_value } from './format';

/** "12.3 ± 1.4 s"; a single run has no spread to show. */
function mean_and_sd(b: Benchmark): string {
  if (b.n < 2) return format_value(b.mean, b.unit);
  return `${format_value(b.mean, '')} ± ${format_value(b.sd, b.unit)}`;
}

/**
 * The expert benchmarks (GET /api/benchmarks): per task and metric, the spread of the values that
 * attempts marked as expert runs scored, which an attempt's review compares against.
 */
export function BenchmarksTable({ benchmarks }: { benchmarks: Benchmark[] }) {
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
              { header: 'Metric', cell: (b) => b.metric },
              { header: 'Runs', cell: (b) => b.n, className: 'numeric' },
              { header: 'Mean ± SD', cell: mean_and_sd, className: 'numeric' },
              { header: 'Median', cell: (b) => format_value(b.median, b.unit), className: 'numeric' },
              {
                header: 'p10–p90',
                cell: (b) => `${format_value(b.p10, '')}–${format_value(b.p90, b.unit)}`,
                className: 'numeric',
              },
            ]}
          />
        </>
      )}
    </div>
  );
}
