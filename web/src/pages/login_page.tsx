import { useState, type SubmitEvent } from 'react';
import { api } from '../api';
import { home_path, useAuth } from '../auth';
import { ErrorAlert, StatusMessage } from '../components/common/alerts';
import { navigate } from '../router';
import { error_text } from '../use_resource';
import { usePageTitle } from '../use_page_title';

export function LoginPage() {
  usePageTitle('Log in');
  const { logged_in, notice } = useAuth();
  const [username, set_username] = useState('');
  const [password, set_password] = useState('');
  const [error, set_error] = useState<string | null>(null);
  const [busy, set_busy] = useState(false);

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    set_busy(true);
    set_error(null);
    try {
      const { user } = await api.login(username.trim(), password);
      logged_in(user);
      navigate(home_path(user.role), { replace: true });
    } catch (reason) {
      set_error(error_text(reason));
      set_password('');
      set_busy(false);
    }
  }

  return (
    <main id="main" tabIndex={-1} className="login-page">
      <section className="card login-card" aria-labelledby="login-title">
        <h1 id="login-title">Log in to Incise</h1>
        <p className="muted">Surgical skills training: book a station, train, follow your scores.</p>
        <StatusMessage message={notice} />
        <form onSubmit={on_submit} className="form">
          <label htmlFor="login-username">Username</label>
          <input
            id="login-username"
            name="username"
            autoComplete="username"
            autoCapitalize="none"
            spellCheck={false}
            required
            autoFocus
            value={username}
            onChange={(e) => set_username(e.target.value)}
          />
          <label htmlFor="login-password">Password</label>
          <input
            id="login-password"
            name="password"
            type="password"
            autoComplete="current-password"
            required
            value={password}
            onChange={(e) => set_password(e.target.value)}
          />
          <ErrorAlert message={error} />
          <button type="submit" className="button-primary" disabled={busy}>
            {busy ? 'Logging in…' : 'Log in'}
          </button>
        </form>
      </section>
    </main>
  );
}
