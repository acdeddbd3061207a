import { api, type ListedUser, type Station } from '../api';
import { AuditLog } from '../components/audit_log';
import { BenchmarksTable } from '../components/benchmarks_table';
import { CalibrationEditor } from '../components/calibration_editor';
import { Card } from '../components/card';
import { CurriculumEditor } from '../components/curriculum_editor';
import { CurriculumImport } from '../components/curriculum_import';
import { InstructorPicker } from '../components/instructor_picker';
import { DataTable } from '../components/data_table';
import { ResourceView } from '../components/resource_view';
import { StationForm, StationKindOptions, StationKindPicker } from '../components/station_form';
import { ThresholdEditor } from '../components/threshold_editor';
import { UserForm } from '../components/user_form';
import { useResource } from '../use_resource';
import { role_label } from './access';

export function AdminPage() {
  const users = useResource(api.users);
  const stations = useResource(api.stations);
  const curricula = useResource(api.curricula);
  const benchmarks = useResource(api.benchmarks);
  const instructors = users.data?.filter((u) => u.role === 'instructor') ?? [];
  // The station kinds the curricula's tasks need: the choices for a station's kind.
  const station_kinds = [
    ...new Set(
      (curricula.data ?? []).flatMap((c) =>
        c.definition.modules.flatMap((m) => m.tasks.map((t) => t.station_kind ?? '')),
      ),
    ),
  ]
    .filter((k) => k)
    .sort();

  return (
    <main className="page">
      <h1>Administration</h1>
      <div className="columns">
        <Card id="users" title="Users" grow>
          <ResourceView resource={users} what="users" empty="No users.">
            {(data) => (
              <DataTable<ListedUser>
                labelled_by="users-title"
                rows={data}
                row_key={(u) => u.id}
                columns={[
                  { header: 'Username', cell: (u) => u.username },
                  { header: 'Display name', cell: (u) => u.display_name },
                  { header: 'Role', cell: (u) => <span className={`role-badge role-${u.role}`}>{role_label(u.role)}</span> },
                  {
                    header: 'Taught by',
                    cell: (u) =>
                      u.role === 'trainee' ? <InstructorPicker trainee={u} instructors={instructors} on_saved={users.reload} /> : '—',
                  },
                ]}
              />
            )}
          </ResourceView>
        </Card>
        <Card id="new-user" title="New user">
          <UserForm on_created={users.reload} />
        </Card>
      </div>
      <div className="columns">
        <Card id="stations" title="Stations" grow>
          <ResourceView resource={stations} what="stations" empty="No stations yet. Create one to let trainees book it.">
            {(data) => (
              <DataTable<Station>
                labelled_by="stations-title"
                rows={data}
                row_key={(s) => s.id}
                columns={[
                  { header: 'Name', cell: (s) => s.name },
                  { header: 'Location', cell: (s) => s.location || '—' },
                  {
                    header: 'Kind',
                    cell: (s) => <StationKindPicker station={s} kinds={station_kinds} on_changed={stations.reload} />,
                  },
                  {
                    header: 'Agent',
                    cell: (s) => (
                      <span className={`badge ${s.online ? 'badge-online' : 'badge-offline'}`}>
                        {s.online ? 'Online' : 'Offline'}
                      </span>
                    ),
                  },
                ]}
              />
            )}
          </ResourceView>
          <button type="button" className="button-quiet button-small" onClick={stations.reload}>
            Refresh status
          </button>
        </Card>
        <Card id="new-station" title="New station">
          <StationForm on_created={stations.reload} />
          <StationKindOptions kinds={station_kinds} />
        </Card>
      </div>
      <Card id="calibration" title="Station calibration">
        {stations.data && <CalibrationEditor stations={stations.data} />}
      </Card>
      <div className="columns">
        <Card id="thresholds" title="Curriculum thresholds" grow>
          {curricula.error && <p role="alert">Could not load the curricula: {curricula.error}</p>}
          {curricula.data?.[0] && <ThresholdEditor curriculum={curricula.data[0]} on_saved={curricula.reload} />}
        </Card>
        <Card id="import" title="Import a curriculum">
          <CurriculumImport on_imported={curricula.reload} />
        </Card>
        <Card id="exports" title="Exports">
          <ul>
            <li>
              <a href="/api/exports/scores.csv" download>
                Scores and attempts (CSV)
              </a>
            </li>
            {curricula.data?.[0] && (
              <li>
                <a href={`/api/curricula/${curricula.data[0].id}/export`} download>
                  {`Curriculum “${curricula.data[0].name}” (JSON)`}
                </a>
              </li>
            )}
          </ul>
        </Card>
      </div>
      <Card id="curriculum-editor" title="Curriculum editor">
        {curricula.data && <CurriculumEditor curricula={curricula.data} on_saved={curricula.reload} />}
      </Card>
      <Card id="benchmarks" title="Expert benchmarks">
        {benchmarks.error && <p role="alert">Could not load the benchmarks: {benchmarks.error}</p>}
        {benchmarks.data && <BenchmarksTable benchmarks={benchmarks.data} />}
      </Card>
      <Card id="audit" title="Audit log">
        <AuditLog />
      </Card>
    </main>
  );
}
