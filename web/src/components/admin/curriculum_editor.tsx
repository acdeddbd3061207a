import { useState, type SubmitEvent } from 'react';
import { api, type CurriculumEntry } from '../../api';
import { parse_json, useFormAction } from '../../use_form_action';
import { ErrorAlert, StatusMessage } from '../common/alerts';

/**
 * A whole curriculum as JSON text to edit: modules, tasks, their metrics, zones, targets, forces
 * and prerequisites (docs/training.md). The server validates what is saved and names the path of
 * the first problem (e.g. `modules[0].tasks[1].prerequisites[0]: unknown task "x"`); nothing is
 * stored until it is valid.
 */
export function CurriculumEditor({ curricula, on_saved }: { curricula: CurriculumEntry[]; on_saved: () => void }) {
  const [chosen_id, set_chosen_id] = useState<number | null>(curricula[0]?.id ?? null);
  const { busy, error, status, run, clear } = useFormAction();
  const chosen = curricula.find((c) => c.id === chosen_id) ?? curricula[0] ?? null;

  // The stored definition, whenever another curriculum is chosen or the list reloads.
  const [text, set_text] = useState(() => definition_text(chosen));
  const [shown, set_shown] = useState(chosen);
  if (shown !== chosen) {
    set_shown(chosen);
    set_text(definition_text(chosen));
  }

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    if (!chosen) return;
    await run(async () => {
      const definition = parse_json(text) as CurriculumEntry['definition'];
      const saved = await api.update_curriculum(chosen.id, definition);
      on_saved();
      return `Saved “${saved.name}”.`;
    }, 'Could not save the curriculum');
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
          clear();
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

function definition_text(entry: CurriculumEntry | null): string {
  return entry ? JSON.stringify(entry.definition, null, 2) : '';
}
