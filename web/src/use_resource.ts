// Every GET of the dashboard goes through TanStack Query (query_client.ts): components that ask
// for the same key share one request and one cached answer, and reload() refetches it for all.
import { useQuery, type QueryKey } from '@tanstack/react-query';
import { useCallback } from 'react';
import { ApiError } from './api';

export interface Resource<T> {
  data: T | null;
  error: string | null;
  /** True while a request for it is under way, the first or a reload. */
  loading: boolean;
  reload: () => void;
}

/**
 * Loads `load()` under `key`, the API path's segments (`['sessions', id, 'review']` for
 * GET /api/sessions/{id}/review): the key names the answer, so two loads with one key must ask
 * for the same thing. A mounted component shows the cached answer at once and refreshes it.
 */
export function useResource<T>(key: QueryKey, load: () => Promise<T>): Resource<T> {
  const query = useQuery({ queryKey: key, queryFn: () => load() });
  const { refetch } = query;
  const reload = useCallback(() => {
    void refetch();
  }, [refetch]);
  return {
    data: query.data ?? null,
    error: query.error ? error_text(query.error) : null,
    loading: query.isFetching,
    reload,
  };
}

export function error_text(reason: unknown): string {
  if (reason instanceof ApiError) return reason.message;
  if (reason instanceof Error) return `Unexpected error: ${reason.message}`;
  return 'Unexpected error.';
}
