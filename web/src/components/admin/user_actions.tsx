import { useState, type SubmitEvent } from 'react';
import { api, type ListedUser } from '../../api';
import { useFormAction } from '../../use_form_action';
import { ErrorAlert, StatusMessage } from '../common/alerts';

/**
 * An admin's actions on one user: disable or re-enable (a disabled user is logged out and cannot
 * log in), and reset the password to a temporary one that the user must replace at their next
 * login. The server refuses both on the admin's own account; the buttons are not offered there.
 */
export function UserActions({ user, self, on_changed }: { user: ListedUser; self: boolean; on_changed: () => void }) {
  const { busy, error, status, run } = useFormAction();
  const [resetting, set_resetting] = useState(false);
  const [password, set_password] = useState('');

  if (self) return <span className="muted">You</span>;

  function toggle_disabled() {
    void run(async () => {
      const next = await api.update_user(user.id, { disabled: !user.disabled });
      on_changed();
      return next.disabled ? `${user.username} is disabled and logged out.` : `${user.username} can log in again.`;
    }, `Could not ${user.disabled ? 're-enable' : 'disable'} ${user.username}`);
  }

  async function on_reset(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    await run(async () => {
      await api.reset_password(user.id, password);
      set_password('');
      set_resetting(false);
      on_changed();
      return `${user.username} must choose a new password at their next login.`;
    }, `Could not reset the password of ${user.username}`);
  }

  return (
    <div className="user-actions">
      <button
        type="button"
        className={user.disabled ? 'button-small' : 'button-small button-danger'}
        disabled={busy}
        data-testid={`user-${user.username}-toggle`}
        onClick={toggle_disabled}
      >
        {user.disabled ? 'Enable' : 'Disable'}
      </button>
      <button
        type="button"
        className="button-small button-quiet"
        disabled={busy}
        aria-expanded={resetting}
        onClick={() => set_resetting((open) => !open)}
      >
        Reset password
      </button>
      {resetting && (
        <form className="inline-form" onSubmit={on_reset} aria-label={`Reset the password of ${user.username}`}>
          <label htmlFor={`reset-${user.id}`}>Temporary password</label>
          <input
            id={`reset-${user.id}`}
            type="password"
            autoComplete="new-password"
            minLength={10}
            required
            value={password}
            onChange={(e) => set_password(e.target.value)}
          />
          <button type="submit" className="button-small button-primary" disabled={busy}>
            Set password
          </button>
        </form>
      )}
      <ErrorAlert message={error} />
      <StatusMessage message={status} />
    </div>
  );
}
