import { api } from '../api';
import { ResourceView } from '../components/resource_view';
import { StationForm } from '../components/station_form';
import { UserForm } from '../components/user_form';
import { useResource } from '../use_resource';
import { role_label } from './access';

export function AdminPage() {
  const users = useResource(api.users);
  const stations = useResource(api.stations);

  return (
    <main className="page">
      <h1>Administration</h1>
      <div className="columns">
        <section className="card grow" aria-labelledby="users-title">
          <h2 id="users-title">Users</h2>
          <ResourceView resource={users} what="users" empty="No users.">
            {(data) => (
              <div className="table-wrap">
                <table aria-labelledby="users-title">
                  <thead>
                    <tr>
                      <th scope="col">Username</th>
                      <th scope="col">Display name</th>
                      <th scope="col">Role</th>
                    </tr>
                  </thead>
                  <tbody>
                    {data.map((u) => (
                      <tr key={u.id}>
                        <td>{u.username}</td>
                        <td>{u.display_name}</td>
                        <td>
                          <span className={`role-badge role-${u.role}`}>{role_label(u.role)}</span>
                        </td>
                      </tr>
                    ))}
                  </tbody>
                </table>
              </div>
            )}
          </ResourceView>
        </section>
        <section className="card" aria-labelledby="new-user-title">
          <h2 id="new-user-title">New user</h2>
          <UserForm on_created={users.reload} />
        </section>
      </div>
      <div className="columns">
        <section className="card grow" aria-labelledby="stations-title">
          <h2 id="stations-title">Stations</h2>
          <ResourceView resource={stations} what="stations" empty="No stations yet. Create one to let trainees book it.">
            {(data) => (
              <div className="table-wrap">
                <table aria-labelledby="stations-title">
                  <thead>
                    <tr>
                      <th scope="col">Name</th>
                      <th scope="col">Location</th>
                      <th scope="col">Agent</th>
                    </tr>
                  </thead>
                  <tbody>
                    {data.map((s) => (
                      <tr key={s.id}>
                        <td>{s.name}</td>
                        <td>{s.location || '—'}</td>
                        <td>
                          <span className={`badge ${s.online ? 'badge-online' : 'badge-offline'}`}>
                            {s.online ? 'Online' : 'Offline'}
                          </span>
                        </td>
                      </tr>
                    ))}
                  </tbody>
                </table>
              </div>
            )}
          </ResourceView>
          <button type="button" className="button-quiet button-small" onClick={stations.reload}>
            Refresh status
          </button>
        </section>
        <section className="card" aria-labelledby="new-station-title">
          <h2 id="new-station-title">New station</h2>
          <StationForm on_created={stations.reload} />
        </section>
      </div>
    </main>
  );
}
