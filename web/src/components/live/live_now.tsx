import { useEffect } from 'react';
import { api, type Session } from '../../api';
import { Link } from '../../router';
import { format_date_time } from '../../time';
import { useResource } from '../../use_resource';
import { DataTable } from '../common/data_table';

const refresh_ms = 10_000;

/**
 * The sessions running (or paused) now among those the viewer may see, each with a link to watch
 * it live; refreshed every ten seconds, so that a session started a moment ago appears.
 */
export function LiveNow() {
  const sessions = useResource(['sessions'], api.sessions);
  const { reload } = sessions;
  useEffect(() => {
    const timer = window.setInterval(reload, refresh_ms);
    return () => window.clearInterval(timer);
  }, [reload]);

  const live = (sessions.data ?? []).filter((s) => s.state === 'running' || s.state === 'paused');
  if (sessions.error) return <p role="alert">Could not load the sessions: {sessions.error}</p>;
  if (live.length === 0) return <p className="empty">No session is running now.</p>;
  return (
    <DataTable<Session>
      rows={live}
      row_key={(s) => s.id}
      labelled_by="live-now-title"
      columns={[
        { header: 'Trainee', cell: (s) => s.trainee },
        { header: 'Task', cell: (s) => s.task },
        { header: 'Station', cell: (s) => s.station || '—' },
        { header: 'Since', cell: (s) => format_date_time(s.started_at) },
        { header: 'State', cell: (s) => <span className={`badge badge-${s.state}`}>{s.state === 'running' ? 'Running' : 'Paused'}</span> },
        {
          header: '',
          cell: (s) => (
            <Link to={`/sessions/${s.id}`} label={`Watch session ${s.id} live`}>
              Watch live
            </Link>
          ),
        },
      ]}
    />
  );
}
