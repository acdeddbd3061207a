import { home_path, useUser } from '../auth';
import { Link } from '../router';
import { usePageTitle } from '../use_page_title';
import { role_label, type PageInfo } from './access';

export function ForbiddenPage({ page }: { page: PageInfo }) {
  const user = useUser();
  usePageTitle('Access denied');
  const allowed = page.roles.map((r) => role_label(r).toLowerCase() + 's').join(' and ');
  return (
    <main id="main" tabIndex={-1} className="page">
      <section className="card notice-card">
        <h1>Access denied</h1>
        <p>
          “{page.title}” is only for {allowed}. You are logged in as {user.display_name} ({role_label(user.role).toLowerCase()}).
        </p>
        <p>
          <Link to={home_path(user.role)}>Go to your page</Link>
        </p>
      </section>
    </main>
  );
}

export function NotFoundPage({ home }: { home: string }) {
  usePageTitle('Page not found');
  return (
    <main id="main" tabIndex={-1} className="page">
      <section className="card notice-card">
        <h1>Page not found</h1>
        <p>There is no page at this address.</p>
        <p>
          <Link to={home}>Go to the start page</Link>
        </p>
      </section>
    </main>
  );
}
