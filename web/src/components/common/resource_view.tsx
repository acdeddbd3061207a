import type { ReactNode } from 'react';
import type { Resource } from '../../use_resource';
import { ErrorAlert } from './alerts';

/** Renders a resource's loading, error and empty states explicitly, and its data otherwise. */
export function ResourceView<T extends unknown[]>({
  resource,
  what,
  empty,
  children,
}: {
  resource: Resource<T>;
  /** Plural noun for the loading message, e.g. "bookings". */
  what: string;
  empty: string;
  children: (data: T) => ReactNode;
}) {
  const { data, error, loading } = resource;
  return (
    <>
      <ErrorAlert message={error && `Could not load ${what}: ${error}`} />
      {loading && data === null && <p className="muted" role="status">Loading {what}…</p>}
      {data !== null && data.length === 0 && <p className="empty">{empty}</p>}
      {data !== null && data.length > 0 && children(data)}
    </>
  );
}
