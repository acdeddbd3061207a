import { useState, type FormEvent } from 'react';
import { api } from '../api';
import { error_text } from '../use_resource';
import { ErrorAlert, StatusMessage } from './alerts';

/**
 * Imports a curriculum file (the format GET /api/curricula/{id}/export downloads) as a new
 * curriculum. The file text goes to the server as it is, after a local check that it is JSON at
 * all; the server checks the rest and names the path of the first problem, or refuses a name in use.
 */
export function CurriculumImport({ on_imported }: { on_imported: () => void }) {
  const [file, set_file] = useState<File | null>(null);
  // Changed after an import to give a fresh, empty file input.
  const [input_generation, set_input_generation] = useState(0);
  const [error, set_error] = useState<string | null>(null);
  const [status, set_status] = useState<string | null>(null);
  const [busy, set_busy] = useState(false);

  async function on_submit(event: FormEvent<HTMLFormElement>) {
    event.preventDefault();
    if (!file) return;
    set_error(null);
    set_status(null);
    set_busy(true);
    try {
      // An editor's byte-order mark is not part of the JSON.
      const text = (await file.text()).replace(/^\uFEFF/, '');
      let definition: unknown;
      try {
        definition = JSON.parse(text);
      } catch (reason) {
        set_error(`Not valid JSON: ${reason instanceof Error ? reason.message : String(reason)}`);
        return;
      }
      // The body is the curriculum definition itself, as in the file; the answer wraps it.
      const created = await api.import_curriculum(definition);
      set_status(`Imported “${created.name}”.`);
      set_file(null);
      set_input_generation((g) => g + 1);
      on_imported();
    } catch (reason) {
      set_error(`Could not import the curriculum: ${error_text(reason)}`);
    } finally {
      set_busy(false);
    }
  }

  return (
    <form className="form" data-testid="curriculum-import" aria-label="Import curriculum" onSubmit={on_submit}>
      <label htmlFor="curriculum-file">Curriculum file</label>
      <input
        key={input_generation}
        id="curriculum-file"
        type="file"
        accept=".json,application/json"
        required
        aria-describedby="curriculum-file-hint"
        onChange={(e) => {
          set_file(e.target.files?.[0] ?? null);
          set_error(null);
          set_status(null);
        }}
      />
      <p className="hint" id="curriculum-file-hint">
        A curriculum in the JSON format of an export. Its name must not be in use yet.
      </p>
      <ErrorAlert message={error} />
      <StatusMessage message={status} />
      <button type="submit" className="button-primary" disabled={busy || !file}>
        {busy ? 'Importing…' : 'Import curriculum'}
      </button>
    </form>
  );
}
