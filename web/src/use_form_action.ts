import { useCallback, useState } from 'react';
import { error_text } from './use_resource';

/** A problem found in the browser before anything was sent (e.g. text that is not JSON). */
export class InputError extends Error {}

/** The JSON value of text, or an InputError "Not valid JSON: …" saying where it breaks. */
export function parse_json(text: string): unknown {
  try {
    return JSON.parse(text);
  } catch (reason) {
    throw new InputError(`Not valid JSON: ${reason instanceof Error ? reason.message : String(reason)}`);
  }
}

export interface FormAction {
  busy: boolean;
  error: string | null;
  status: string | null;
  /**
   * Runs `action` (a save, an import…) while `busy`: its answer, when it returns one, becomes the
   * status message; a failure becomes the error, as "<failure>: <the server's words>" (an
   * InputError as it is).
   */
  run: (action: () => Promise<string | undefined>, failure: string) => Promise<void>;
  /** Clears the error and status, e.g. when the person changes what the form is about. */
  clear: () => void;
  set_error: (message: string | null) => void;
}

/** The busy flag, error and status message every form of the dashboard shows around its action. */
export function useFormAction(): FormAction {
  const [busy, set_busy] = useState(false);
  const [error, set_error] = useState<string | null>(null);
  const [status, set_status] = useState<string | null>(null);

  const run = useCallback(async (action: () => Promise<string | undefined>, failure: string) => {
    set_busy(true);
    set_error(null);
    set_status(null);
    try {
      const done = await action();
      if (done) set_status(done);
    } catch (reason) {
      set_error(reason instanceof InputError ? reason.message : `${failure}: ${error_text(reason)}`);
    } finally {
      set_busy(false);
    }
  }, []);
  const clear = useCallback(() => {
    set_error(null);
    set_status(null);
  }, []);
  return { busy, error, status, run, clear, set_error };
}
