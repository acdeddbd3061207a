import { useState, type SubmitEvent } from 'react';
import { api } from '../../api';
import { useFormAction } from '../../use_form_action';
import { ErrorAlert } from '../common/alerts';

const max_name_length = 80;

/**
 * Saves a done job's calibrated constants as a named tissue material (POST /api/materials), for
 * curricula to name. The server refuses (409) a name in use. `on_saved` gets the saved name: the
 * caller says it was saved, in place of the form.
 */
export function MaterialForm({ job_id, on_saved }: { job_id: number; on_saved: (name: string) => void }) {
  const [name, set_name] = useState('');
  const { busy, error, run, clear } = useFormAction();

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    const chosen = name.trim();
    if (!chosen) return;
    await run(async () => {
      const saved = await api.save_material(job_id, chosen);
      on_saved(saved.name);
      return undefined;
    }, 'Could not save the material');
  }

  return (
    <form className="inline-form" aria-label="Save material" data-testid="material-form" onSubmit={on_submit}>
      <label htmlFor={`material-name-${job_id}`}>Material name</label>
      <input
        id={`material-name-${job_id}`}
        required
        maxLength={max_name_length}
        value={name}
        disabled={busy}
        onChange={(e) => {
          set_name(e.target.value);
          clear();
        }}
      />
      <button type="submit" className="button-primary" disabled={busy || !name.trim()}>
        {busy ? 'Saving…' : 'Save material'}
      </button>
      <ErrorAlert message={error} />
    </form>
  );
}
