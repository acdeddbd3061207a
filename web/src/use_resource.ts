import { useCallback, useEffect, useState } from 'react';
import { ApiError } from './api';

export interface Resource<T> {
  data: T | null;
  error: string | null;
  loading: boolean;
  reload: () => void;
}

/** Loads `load()` on mount and on every reload(); `load` must be a stable function. */
export function useResource<T>(load: () => Promise<T>): Resource<T> {
  const [data, set_data] = useState<T | null>(null);
  const [error, set_error] = useState<string | null>(null);
  const [loading, set_loading] = useState(true);
  const [generation, set_generation] = useState(0);

  useEffect(() => {
    let current = true;
    set_loading(true);
    load().then(
      (value) => {
        if (!current) return;
        set_data(value);
        set_error(null);
        set_loading(false);
      },
      (reason: unknown) => {
        if (!current) return;
        set_error(error_text(reason));
        set_loading(false);
      },
    );
    return () => {
      current = false;
    };
  }, [load, generation]);

  const reload = useCallback(() => set_generation((g) => g + 1), []);
  return { data, error, loading, reload };
}

export function error_text(reason: unknown): string {
  if (reason instanceof ApiError) return reason.message;
  if (reason instanceof Error) return `Unexpected error: ${reason.message}`;
  return 'Unexpected error.';
}
