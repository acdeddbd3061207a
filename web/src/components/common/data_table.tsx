import type { Key, ReactNode } from 'react';

/** One column: its header and how a row fills its cell; `className` goes on both (e.g. "numeric"). */
export interface Column<Row> {
  header: ReactNode;
  cell: (row: Row) => ReactNode;
  className?: string;
}

/**
 * A scrollable table with a header row and one row per item. Columns may be given as `false` so that
 * a caller can write `show_trainee && trainee_column`. The empty state is not here: callers render
 * the table only once there is data (see ResourceView), so an empty table never appears.
 */
export function DataTable<Row>({
  columns,
  rows,
  row_key,
  row_class,
  labelled_by,
}: {
  columns: readonly (Column<Row> | false)[];
  rows: readonly Row[];
  row_key: (row: Row) => Key;
  /** Extra class of a row, e.g. to grey out cancelled ones. */
  row_class?: (row: Row) => string | undefined;
  /** Id of the heading that names the table. */
  labelled_by?: string;
}) {
  const shown = columns.filter((column) => column !== false);
  // The columns of one table are fixed for a render, so their position is a stable key.
  return (
    <div className="table-wrap">
      <table aria-labelledby={labelled_by}>
        <thead>
          <tr>
            {shown.map((column, i) => (
              <th key={i} scope="col" className={column.className}>
                {column.header}
              </th>
            ))}
          </tr>
        </thead>
        <tbody>
          {rows.map((row) => (
            <tr key={row_key(row)} className={row_class?.(row)}>
              {shown.map((column, i) => (
                <td key={i} className={column.className}>
                  {column.cell(row)}
                </td>
              ))}
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
