import { QueryClient } from '@tanstack/react-query';

/**
 * The dashboard's one request cache. An answer is shown from the cache and refreshed when a
 * component that needs it mounts; a failure is shown at once (no retries: the person decides),
 * and nothing refetches behind their back when the window regains focus.
 */
export function make_query_client(): QueryClient {
  return new QueryClient({
    defaultOptions: {
      queries: { retry: false, refetchOnWindowFocus: false },
    },
  });
}
