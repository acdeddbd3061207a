import { useState, type SubmitEvent } from 'react';
import { api } from '../api';
import { home_path, useAuth } from '../auth';
import { ErrorAlert } from '../components/common/alerts';
import { navigate } from '../router';
import { useFormAction } from '../use_form_action';
import { usePageTitle } from '../use_page_title';

/**
 * `/password`: choose a new password. After an admin reset it this is the only page the person can
 * use (the server refuses everything else until they have); otherwise anyone may change theirs.
 */
export function ChangePasswordPage() {
  usePageTitle('Choose a new password');
  const { user, logged_in } = useAuth();
  const [current, set_current] = useState('');
  const [next, set_next] = useState('');
  const [repeat, set_repeat] = useState('');
  const { busy, error, run, set_error } = useFormAction();
  const forced = user?.must_change_password ?? false;

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    if (next !== repeat) {
      set_error('The two new passwords differ.');
      return;
    }
    await run(async () => {
      const changed = await api.change_password(current, next);
      logged_in(changed);
      navigate(home_path(changed.role), { replace: true });
      return undefined;
    }, 'Could not change your password');
  }

  return (
    <main id="main" tabIndex={-1} className="login-page">
      <section className="card login-card" aria-labelledby="password-title">
        <h1 id="password-title">Choose a new password</h1>
        {forced && (
          <p className="alert alert-info" data-testid="password-reset-notice">
            An admin reset your password. Choose one of your own to continue.
          </p>
        )}
        <form onSubmit={on_submit} className="form">
          <label htmlFor="password-current">{forced ? 'Temporary password' : 'Current password'}</label>
          <input
            id="password-current"
            type="password"
            autoComplete="current-password"
            required
            value={current}
            onChange={(e) => set_current(e.target.value)}
          />
          <label htmlFor="password-new">New password</label>
          <input
            id="password-new"
            type="password"
            autoComplete="new-password"
            minLength={10}
            required
            aria-describedby="password-new-hint"
            value={next}
            onChange={(e) => set_next(e.target.value)}
          />
          <p className="hint" id="password-new-hint">
            At least 10 characters.
          </p>
          <label htmlFor="password-repeat">New password again</label>
          <input
            id="password-repeat"
            type="password"
            autoComplete="new-password"
            required
            value={repeat}
            onChange={(e) => set_repeat(e.target.value)}
          />
          <ErrorAlert message={error} />
          <button type="submit" className="button-primary" disabled={busy}>
            {busy ? 'Saving…' : 'Save the new password'}
          </button>
        </form>
      </section>
    </main>
  );
}
