import { useState, type SubmitEvent } from 'react';
import { api, type Role, type User } from '../../api';
import { role_label } from '../../pages/access';
import { useFormAction } from '../../use_form_action';
import { ErrorAlert, StatusMessage } from '../common/alerts';

const roles: Role[] = ['trainee', 'instructor', 'admin'];

export function UserForm({ on_created }: { on_created: (user: User) => void }) {
  const [username, set_username] = useState('');
  const [display_name, set_display_name] = useState('');
  const [role, set_role] = useState<Role>('trainee');
  const [password, set_password] = useState('');
  const { busy, error, status, run } = useFormAction();

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    await run(async () => {
      const user = await api.create_user({ username: username.trim(), display_name: display_name.trim(), role, password });
      set_username('');
      set_display_name('');
      set_password('');
      on_created(user);
      return `Created ${role_label(user.role).toLowerCase()} “${user.username}”.`;
    }, 'Could not create the user');
  }

  return (
    <form onSubmit={on_submit} className="form" aria-label="Create user">
      <label htmlFor="user-username">Username</label>
      <input
        id="user-username"
        autoComplete="off"
        autoCapitalize="none"
        spellCheck={false}
        required
        aria-describedby="user-username-hint"
        value={username}
        onChange={(e) => set_username(e.target.value)}
      />
      <p className="hint" id="user-username-hint">
        3–32 characters: lower-case letters, digits, “.”, “_” and “-”.
      </p>
      <label htmlFor="user-display-name">Display name</label>
      <input id="user-display-name" required value={display_name} onChange={(e) => set_display_name(e.target.value)} />
      <label htmlFor="user-role">Role</label>
      <select id="user-role" value={role} onChange={(e) => set_role(e.target.value as Role)}>
        {roles.map((r) => (
          <option key={r} value={r}>
            {role_label(r)}
          </option>
        ))}
      </select>
      <label htmlFor="user-password">Password</label>
      <input
        id="user-password"
        type="password"
        autoComplete="new-password"
        required
        aria-describedby="user-password-hint"
        value={password}
        onChange={(e) => set_password(e.target.value)}
      />
      <p className="hint" id="user-password-hint">
        At least 10 characters. Give it to the person over a safe channel.
      </p>
      <ErrorAlert message={error} />
      <StatusMessage message={status} />
      <button type="submit" className="button-primary" disabled={busy}>
        {busy ? 'Creating…' : 'Create user'}
      </button>
    </form>
  );
}
