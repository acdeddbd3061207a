import { api, type AuditEntry } from '../../api';
import { format_date_time } from '../../time';
import { useResource } from '../../use_resource';
import { DataTable } from '../common/data_table';
import { ResourceView } from '../common/resource_view';

// Newest first by id, which grows with every entry (the server sends them so; this keeps it true).
const load_audit = () =>
  api.audit().then((entries) => [...entries].sort((a, b) => b.id - a.id));

/**
 * The audit log of administrative changes, newest first. Entries name their author by user id,
 * so the users list (also admin-only) supplies the names.
 */
export function AuditLog() {
  const entries = useResource(['audit'], load_audit);
  const users = useResource(['users'], api.users);

  const who = (user_id: number | null): string => {
    if (user_id === null) return 'System';
    const user = users.data?.find((u) => u.id === user_id);
    return user ? `${user.display_name} (${user.username})` : `User ${user_id}`;
  };

  return (
    <div className="audit-log" data-testid="audit-log">
      <span id="audit-log-label" className="visually-hidden">
        Audit log
      </span>
      <ResourceView resource={entries} what="the audit log" empty="Nothing recorded yet.">
        {(data) => (
          <DataTable<AuditEntry>
            labelled_by="audit-log-label"
            rows={data}
            row_key={(e) => e.id}
            columns={[
              { header: 'Time', cell: (e) => <time dateTime={e.at}>{format_date_time(e.at)}</time> },
              { header: 'Who', cell: (e) => who(e.user_id) },
              { header: 'Action', cell: (e) => <code>{e.action}</code> },
              { header: 'Detail', cell: (e) => e.detail || '—' },
              { header: 'Change', cell: (e) => <AuditChange entry={e} /> },
            ]}
          />
        )}
      </ResourceView>
      <button
        type="button"
        className="button-quiet button-small"
        disabled={entries.loading}
        onClick={() => {
          entries.reload();
          users.reload();
        }}
      >
        Refresh
      </button>
    </div>
  );
}

/** A value as the log shows it: text as it is, anything else as compact JSON, long ones cut. */
function shown(value: unknown): string {
  if (value === null || value === undefined) return '—';
  const text = typeof value === 'string' ? `“${value}”` : JSON.stringify(value);
  return text.length > 80 ? `${text.slice(0, 79)}…` : text;
}

/** Before → after for each field the change changed; a creation lists what it created. */
export function AuditChange({ entry }: { entry: AuditEntry }) {
  const keys = [...new Set([...Object.keys(entry.before ?? {}), ...Object.keys(entry.after ?? {})])];
  if (keys.length === 0) return <span className="muted">—</span>;
  return (
    <ul className="audit-change" data-testid={`audit-change-${entry.id}`}>
      {keys.map((key) => (
        <li key={key}>
          <code>{key}</code>:{' '}
          {entry.before ? (
            <>
              <span className="audit-before">{shown(entry.before[key])}</span> →{' '}
            </>
          ) : null}
          <span className="audit-after">{shown(entry.after?.[key])}</span>
        </li>
      ))}
    </ul>
  );
}
