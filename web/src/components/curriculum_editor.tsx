import { useEffect, useState, type FormEvent } from 'react';
import { api, type CurriculumEntry } from '../api';
import { error_text } from '../use_resource';
import { ErrorAlert, StatusMessage } from './alerts';

/**
 * A whole curriculum as JSON text to edit: modules, tasks, their metrics, zones, targets, forces
 * and prerequisites (docs/training.md). The server validates what is saved and names the path of
 * the first problem (e.g. `modules[0].tasks[1].prerequisites[0]: unknown task "x"`); nothing is
 * stored until it is valid.
 */
export function CurriculumEditor({ curricula, on_saved }: { curricula: CurriculumEntry[]; on_saved: () => void }) {
  const [chosen_id, set_chosen_id] = useState<number | null>(curricula[0]?.id ?? null);
  const [text, set_text] = useState('');
  const [error, set_error] = useState<string | null>(null);
  const [status, set_status] = useState<string | null>(null);
  const [busy, set_busy] = useState(false);
  const chosen = curricula.find((c) => c.id === chosen_id) ?? curricula[0] ?? null;

  // The stored definition, whenever another curriculum is chosen or the list reloads.
  useEffect(() => {
    set_text(chosen ? JSON.stringify(chosen.definition, null, 2) : '');
  }, [chosen]);

  async function on_submit(event: FormEvent<HTMLFormElement>) {
    event.preventDefault();
    if (!chosen) return;
    set_error(null);
    set_status(null);
    let definition: CurriculumEntry['definition'];
    try {
      definition = JSON.parse(text) as CurriculumEntry['definition'];
    } catch (reason) {
      set_error(`Not valid JSON: ${reason instanceof Error ? reason.message : String(reason)}`);
      return;
    }
    set_busy(true);
    try {
      const saved = await api.update_curriculum(chosen.id, definition);
      set_status(`Saved “${saved.name}”.`);
      on_saved();
    } catch (reason) {
      set_error(`Could not save the curriculum: ${error_text(reason)}`);
    } finally {
      set_busy(false);
    }
  }

  if (!chosen) return <p className="empty">No curricula yet. Import one.</p>;
  return (
    <form className="form" data-testid="curriculum-editor" aria-label="Edit curriculum" onSubmit={on_submit}>
      <label htmlFor="curriculum-editor-choice">Curriculum</label>
      <select
        id="curriculum-editor-choice"
        value={chosen.id}
        disabled={busy}
        onChange={(e) => {
          set_chosen_id(Number(e.target.value));
          set_error(null);
          set_status(null);
        }}
      >
        {curricula.map((c) => (
          <option key={c.id} value={c.id}>
            {c.name}
          </option>
        ))}
      </select>
      <textarea
        className="calibration-text"
        aria-label="Curriculum JSON"
        spellCheck={false}
        rows={20}
        value={text}
        onChange={(e) => set_text(e.target.value)}
      />
      <p className="hint">The whole definition: tasks, metrics and thresholds, zones, targets, forces, prerequisites.</p>
      <ErrorAlert message={error} />
      <StatusMessage message={status} />
      <button type="submit" className="button-primary" disabled={busy}>
        {busy ? 'Saving…' : 'Save curriculum'}
      </button>
    </form>
  );
}
