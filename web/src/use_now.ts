import { useEffect, useState } from 'react';

/** The time [ms since the epoch], refreshed every `period_ms`: "now" that re-renders as it moves. */
export function useNow(period_ms: number): number {
  const [now, set_now] = useState(Date.now);
  useEffect(() => {
    const timer = window.setInterval(() => set_now(Date.now()), period_ms);
    return () => window.clearInterval(timer);
  }, [period_ms]);
  return now;
}
