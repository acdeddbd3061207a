import type { ReactNode } from 'react';
import { home_path, useAuth } from './auth';
import { ErrorAlert } from './components/alerts';
import { Header } from './components/header';
import { pages } from './pages/access';
import { AdminPage } from './pages/admin_page';
import { InstructorPage } from './pages/instructor_page';
import { LoginPage } from './pages/login_page';
import { ForbiddenPage, NotFoundPage } from './pages/simple_pages';
import { TraineePage } from './pages/trainee_page';
import { Redirect, usePath } from './router';

const page_components: Record<string, () => ReactNode> = {
  '/trainee': () => <TraineePage />,
  '/instructor': () => <InstructorPage />,
  '/admin': () => <AdminPage />,
};

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
    const page = pages.find((p) => p.path === path);
    const render = page_components[path];
    if (!page || !render) content = <NotFoundPage home={home_path(user.role)} />;
    else if (!page.roles.includes(user.role)) content = <ForbiddenPage page={page} />;
    else content = render();
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
