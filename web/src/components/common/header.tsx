import { useState, type MouseEvent } from 'react';
import { useAuth } from '../../auth';
import { Link } from '../../router';
import { error_text } from '../../use_resource';
import { ErrorAlert } from './alerts';
import { pages_for, role_label } from '../../pages/access';

export function Header() {
  const { user, log_out } = useAuth();
  const [error, set_error] = useState<string | null>(null);
  const [busy, set_busy] = useState(false);

  async function on_log_out() {
    set_busy(true);
    set_error(null);
    try {
      await log_out();
    } catch (reason) {
      set_error(`Could not log out: ${error_text(reason)}`);
    } finally {
      set_busy(false);
    }
  }

  return (
    <header className="app-header">
      <SkipLink />
      <div className="header-inner">
        <span className="brand">Incise</span>
        {user && (
          <>
            <nav aria-label="Main">
              {pages_for(user.role).map((page) => (
                <Link key={page.path} to={page.path}>
                  {page.title}
                </Link>
              ))}
            </nav>
            <div className="who" aria-label="Logged in user">
              <span className="who-name">{user.display_name}</span>
              <span className={`role-badge role-${user.role}`}>{role_label(user.role)}</span>
              <Link to="/password" className="header-link">
                Password
              </Link>
              <button type="button" className="button-quiet" onClick={on_log_out} disabled={busy}>
                Log out
              </button>
            </div>
          </>
        )}
      </div>
      <ErrorAlert message={error} />
    </header>
  );
}

/**
 * The first thing Tab reaches: moves the keyboard focus past the header to the page's
 * `<main id="main" tabIndex={-1}>`. Hidden until focused (styles.css, .skip-link).
 */
export function SkipLink() {
  function on_click(event: MouseEvent<HTMLAnchorElement>) {
    event.preventDefault();
    document.getElementById('main')?.focus();
  }
  return (
    <a className="skip-link" href="#main" onClick={on_click}>
      Skip to content
    </a>
  );
}
