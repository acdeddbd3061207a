import type { ReactNode } from 'react';
import type { Role } from './api';
import { home_path, useAuth } from './auth';
import { ErrorAlert } from './components/common/alerts';
import { Header } from './components/common/header';
import { pages } from './pages/access';
import { AdminPage, is_admin_section } from './pages/admin_page';
import { ChangePasswordPage } from './pages/change_password_page';
import { InstructorPage } from './pages/instructor_page';
import { LoginPage } from './pages/login_page';
import { RecordingPage } from './pages/recording_page';
import { SessionPage } from './pages/session_page';
import { ForbiddenPage, NotFoundPage } from './pages/simple_pages';
import { TraineePage } from './pages/trainee_page';
import { Redirect, usePath } from './router';

const page_components: Record<string, () => ReactNode> = {
  '/trainee': () => <TraineePage />,
  '/instructor': () => <InstructorPage />,
};

// Pages of one session or recording, open to every role: the server decides who may see which
// (the owner, instructors and admins), and the page shows its refusal.
const detail_pages: { pattern: RegExp; render: (id: number) => ReactNode }[] = [
  { pattern: /^\/sessions\/(\d+)$/, render: (id) => <SessionPage key={id} id={id} /> },
  { pattern: /^\/recordings\/(\d+)$/, render: (id) => <RecordingPage key={id} id={id} /> },
];

function detail_page(path: string): ReactNode | null {
  for (const { pattern, render } of detail_pages) {
    const match = pattern.exec(path);
    if (match) return render(Number(match[1]));
  }
  return null;
}

function role_page(path: string, role: Role): ReactNode {
  // The administration is one page per area: /admin/users, /admin/stations, …
  const admin = /^\/admin(?:\/([a-z]+))?$/.exec(path);
  if (admin) {
    const page = pages.find((p) => p.path === '/admin');
    if (page && !page.roles.includes(role)) return <ForbiddenPage page={page} />;
    if (!admin[1]) return <Redirect to="/admin/users" />;
    if (!is_admin_section(admin[1])) return <NotFoundPage home={home_path(role)} />;
    return <AdminPage section={admin[1]} />;
  }
  const page = pages.find((p) => p.path === path);
  const render = page_components[path];
  if (!page || !render) return <NotFoundPage home={home_path(role)} />;
  if (!page.roles.includes(role)) return <ForbiddenPage page={page} />;
  return render();
}

export function App() {
  const { user, start_error } = useAuth();
  const path = usePath().replace(/\/+$/, '') || '/';

  let content: ReactNode;
  if (user === undefined) {
    content = (
      <main id="main" tabIndex={-1} className="page">
        <p className="muted" role="status">
          Loading…
        </p>
      </main>
    );
  } else if (path === '/login') {
    content = user ? <Redirect to={home_path(user.role)} /> : <LoginPage />;
  } else if (!user) {
    content = <Redirect to="/login" />;
  } else if (user.must_change_password || path === '/password') {
    // After an admin's reset the server answers nothing else until a new password is chosen.
    content = path === '/password' ? <ChangePasswordPage /> : <Redirect to="/password" />;
  } else if (path === '/') {
    content = <Redirect to={home_path(user.role)} />;
  } else {
    content = detail_page(path) ?? role_page(path, user.role);
  }

  return (
    <>
      <Header />
      {start_error && (
        <div className="page-alert">
          <ErrorAlert message={start_error} />
        </div>
      )}
      {content}
    </>
  );
}
