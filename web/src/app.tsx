import type { ReactNode } from 'react';
import type { Role } from './api';
import { home_path, useAuth } from './auth';
import { ErrorAlert } from './components/alerts';
import { Header } from './components/header';
import { pages } from './pages/access';
import { AdminPage } from './pages/admin_page';
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
  '/admin': () => <AdminPage />,
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
      <main className="page">
        <p className="muted" role="status">
          Loading…
        </p>
      </main>
    );
  } else if (path === '/login') {
    content = user ? <Redirect to={home_path(user.role)} /> : <LoginPage />;
  } else if (!user) {
    content = <Redirect to="/login" />;
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
