import { useEffect } from 'react';

/** Sets the browser tab's title to "<page> · Incise" while the page is shown. */
export function usePageTitle(page: string): void {
  useEffect(() => {
    document.title = `${page} · Incise`;
  }, [page]);
}
