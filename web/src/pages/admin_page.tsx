import { useState, type ReactNode } from 'react';
import { api, type ListedUser, type Station } from '../api';
import { useAuth } from '../auth';
import { AuditLog } from '../components/admin/audit_log';
import { CalibrationEditor } from '../components/admin/calibration_editor';
import { CurriculumEditor } from '../components/admin/curriculum_editor';
import { CurriculumImport } from '../components/admin/curriculum_import';
import { StationForm, StationKindOptions, StationKindPicker } from '../components/admin/station_form';
import { StationRetire } from '../components/admin/station_retire';
import { ThresholdEditor } from '../components/admin/threshold_editor';
import { UserActions } from '../components/admin/user_actions';
import { UserForm } from '../components/admin/user_form';
import { InstructorPicker } from '../components/booking/instructor_picker';
import { Card } from '../components/common/card';
import { DataTable } from '../components/common/data_table';
import { ResourceView } from '../components/common/resource_view';
import { BenchmarksTable } from '../components/review/benchmarks_table';
import { CalibrationForm } from '../components/tissue/calibration_form';
import { CalibrationJobs, useCalibrationJobs } from '../components/tissue/calibration_jobs';
import { CalibrationResult } from '../components/tissue/calibration_result';
import { MaterialsTable } from '../components/tissue/materials_table';
import { Link } from '../router';
import { useResource } from '../use_resource';
import { usePageTitle } from '../use_page_title';
import { role_label } from './access';

/** The administration's areas, each its own page under /admin/<key>. */
export const admin_sections = [
  { key: 'users', title: 'Users' },
  { key: 'stations', title: 'Stations' },
  { key: 'curricula', title: 'Curricula' },
  { key: 'experts', title: 'Experts' },
  { key: 'calibration', title: 'Tissue calibration' },
  { key: 'exports', title: 'Exports' },
  { key: 'audit', title: 'Audit log' },
] as const;
export type AdminSection = (typeof admin_sections)[number]['key'];

export function is_admin_section(key: string): key is AdminSection {
  return admin_sections.some((s) => s.key === key);
}

const sections: Record<AdminSection, () => ReactNode> = {
  users: () => <UsersSection />,
  stations: () => <StationsSection />,
  curricula: () => <CurriculaSection />,
  experts: () => <ExpertsSection />,
  calibration: () => <TissueCalibrationSection />,
  exports: () => <ExportsSection />,
  audit: () => (
    <Card id="audit" title="Audit log">
      <AuditLog />
    </Card>
  ),
};

export function AdminPage({ section }: { section: AdminSection }) {
  const title = admin_sections.find((s) => s.key === section)?.title ?? 'Administration';
  usePageTitle(`${title} · Administration`);
  return (
    <main id="main" tabIndex={-1} className="page">
      <h1>Administration</h1>
      <nav aria-label="Administration" className="sub-nav">
        {admin_sections.map((s) => (
          <Link key={s.key} to={`/admin/${s.key}`}>
            {s.title}
          </Link>
        ))}
      </nav>
      {sections[section]()}
    </main>
  );
}

function UsersSection() {
  const { user: me } = useAuth();
  const users = useResource(['users'], api.users);
  const instructors = users.data?.filter((u) => u.role === 'instructor') ?? [];
  return (
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
                  header: 'Status',
                  cell: (u) => (
                    <span className={`badge ${u.disabled ? 'badge-offline' : 'badge-online'}`} data-testid={`user-${u.username}-status`}>
                      {u.disabled ? 'Disabled' : u.must_change_password ? 'Must choose a password' : 'Active'}
                    </span>
                  ),
                },
                {
                  header: 'Taught by',
                  cell: (u) =>
                    u.role === 'trainee' ? <InstructorPicker trainee={u} instructors={instructors} on_saved={users.reload} /> : '—',
                },
                { header: 'Actions', cell: (u) => <UserActions user={u} self={u.id === me?.id} on_changed={users.reload} /> },
              ]}
            />
          )}
        </ResourceView>
      </Card>
      <Card id="new-user" title="New user">
        <UserForm on_created={users.reload} />
      </Card>
    </div>
  );
}

/** The station kinds the curricula's tasks need: the choices for a station's kind. */
function useStationKinds(): string[] {
  const curricula = useResource(['curricula'], api.curricula);
  return [
    ...new Set(
      (curricula.data ?? []).flatMap((c) => c.definition.modules.flatMap((m) => m.tasks.map((t) => t.station_kind ?? ''))),
    ),
  ]
    .filter((k) => k)
    .sort();
}

function StationsSection() {
  const stations = useResource(['stations'], api.stations);
  const station_kinds = useStationKinds();
  return (
    <>
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
                    cell: (s) =>
                      s.retired ? (
                        <span className="badge badge-offline" data-testid={`station-${s.id}-state`}>
                          Retired
                        </span>
                      ) : (
                        <span className={`badge ${s.online ? 'badge-online' : 'badge-offline'}`} data-testid={`station-${s.id}-state`}>
                          {s.online ? 'Online' : 'Offline'}
                        </span>
                      ),
                  },
                  { header: 'Service', cell: (s) => <StationRetire station={s} on_changed={stations.reload} /> },
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
    </>
  );
}

function CurriculaSection() {
  const curricula = useResource(['curricula'], api.curricula);
  return (
    <>
      <div className="columns">
        <Card id="thresholds" title="Curriculum thresholds" grow>
          {curricula.error && <p role="alert">Could not load the curricula: {curricula.error}</p>}
          {curricula.data?.[0] && <ThresholdEditor curriculum={curricula.data[0]} on_saved={curricula.reload} />}
        </Card>
        <Card id="import" title="Import a curriculum">
          <CurriculumImport on_imported={curricula.reload} />
        </Card>
      </div>
      <Card id="curriculum-editor" title="Curriculum editor (JSON)">
        {curricula.data && <CurriculumEditor curricula={curricula.data} on_saved={curricula.reload} />}
      </Card>
    </>
  );
}

function ExpertsSection() {
  const benchmarks = useResource(['benchmarks'], api.benchmarks);
  return (
    <Card id="benchmarks" title="Expert benchmarks">
      <p className="hint">
        Instructors and admins record expert runs from their Train page (“Record as an expert run”), or mark a finished
        attempt of their own as one from its review. Each task's band is drawn from these runs.
      </p>
      {benchmarks.error && <p role="alert">Could not load the benchmarks: {benchmarks.error}</p>}
      {benchmarks.data && <BenchmarksTable benchmarks={benchmarks.data} />}
    </Card>
  );
}

function TissueCalibrationSection() {
  const jobs = useCalibrationJobs();
  const materials = useResource(['materials'], api.materials);
  const [selected, set_selected] = useState<number | null>(null);
  const selected_job = jobs.data?.find((j) => j.id === selected);
  const { reload: reload_jobs } = jobs;
  const { reload: reload_materials } = materials;
  return (
    <>
      <div className="columns">
        <Card id="new-calibration" title="New calibration">
          <CalibrationForm
            shown_job={selected_job}
            on_created={(job) => {
              set_selected(job.id);
              reload_jobs();
            }}
          />
        </Card>
        <Card id="calibration-jobs" title="Calibration runs" grow>
          <ResourceView resource={jobs} what="calibration runs" empty="No calibration has run yet.">
            {(data) => (
              <CalibrationJobs jobs={data} selected={selected} on_select={set_selected} on_changed={reload_jobs} />
            )}
          </ResourceView>
        </Card>
      </div>
      {selected_job && (
        <Card id="calibration-result" title={`Calibration run #${selected_job.id}`}>
          <CalibrationResult
            key={selected_job.id}
            job={selected_job}
            on_saved={() => {
              reload_materials();
              reload_jobs();
            }}
          />
        </Card>
      )}
      <Card id="materials" title="Tissue materials">
        <p className="hint">
          A task uses a material when its curriculum names it: in the <Link to="/admin/curricula">Curricula</Link> editor,
          add <code>{`"material": ${JSON.stringify(materials.data?.[0]?.name ?? 'Calibrated cube')}`}</code> to the
          task's object. “Used by” lists the tasks that do.
        </p>
        <ResourceView resource={materials} what="materials" empty="No material saved yet. Save one from a done calibration.">
          {(data) => <MaterialsTable materials={data} />}
        </ResourceView>
      </Card>
    </>
  );
}

function ExportsSection() {
  const curricula = useResource(['curricula'], api.curricula);
  return (
    <Card id="exports" title="Exports">
      <ul>
        <li>
          <a href="/api/exports/scores.csv" download>
            Scores and attempts (CSV)
          </a>
        </li>
        {curricula.data?.map((c) => (
          <li key={c.id}>
            <a href={`/api/curricula/${c.id}/export`} download>
              {`Curriculum “${c.name}” (JSON)`}
            </a>
          </li>
        ))}
      </ul>
    </Card>
  );
}
