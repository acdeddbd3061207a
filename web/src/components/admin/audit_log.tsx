import { api, type AuditEntry } from '../api';
import { format_date_time } from '../time';
import { useResource } from '../use_resource';
import { DataTable } from './data_table';
import { ResourceView } from './resource_view';

// Newest first by id, which grows with every entry (the server sends them so; this keeps it true).
const load_audit = () =>
  api.audit().then((entries) => [...entries].sort((a, b) => b.id - a.id));

/**
 * The audit log of administrative changes, newest first. Entries name their author by user id,
 * so the users list (also admin-only) supplies the names.
 */
export function AuditLog() {
  const entries = useResource(load_audit);
  const users = useResource(api.users);

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
