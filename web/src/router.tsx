// A minimal client-side router: the app has a handful of flat pages, so the History API and one
// external store are all it needs. The server falls back to index.html for every non-/api path,
// so each page also works on reload.
import { useEffect, useSyncExternalStore, type MouseEvent, type ReactNode } from 'react';

const listeners = new Set<() => void>();

function subscribe(listener: () => void): () => void {
  listeners.add(listener);
  window.addEventListener('popstate', listener);
  return () => {
    listeners.delete(listener);
    window.removeEventListener('popstate', listener);
  };
}

function current_path(): string {
  return window.location.pathname;
}

export function navigate(path: string, options: { replace?: boolean } = {}): void {
  if (path === current_path()) return;
  if (options.replace) window.history.replaceState(null, '', path);
  else window.history.pushState(null, '', path);
  for (const listener of listeners) listener();
}

export function usePath(): string {
  return useSyncExternalStore(subscribe, current_path);
}

/** Replaces the current history entry with `to` as soon as it renders. */
export function Redirect({ to }: { to: string }) {
  useEffect(() => navigate(to, { replace: true }), [to]);
  return null;
}

export function Link({
  to,
  children,
  className,
  label,
}: {
  to: string;
  children: ReactNode;
  className?: string;
  /** aria-label, when the visible text alone does not say where the link goes. */
  label?: string;
}) {
  const path = usePath();
  // A section's link stays current on its sub-pages (/admin on /admin/users).
  const active = path === to || (to !== '/' && path.startsWith(`${to}/`));
  function on_click(event: MouseEvent<HTMLAnchorElement>) {
    // Let the browser handle new-tab and other modified clicks.
    if (event.button !== 0 || event.metaKey || event.ctrlKey || event.shiftKey || event.altKey) return;
    event.preventDefault();
    navigate(to);
  }
  return (
    <a href={to} onClick={on_click} className={className} aria-label={label} aria-current={active ? 'page' : undefined}>
      {children}
    </a>
  );
}
