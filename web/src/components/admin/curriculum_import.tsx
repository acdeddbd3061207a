import { useState, type SubmitEvent } from 'react';
import { api } from '../../api';
import { parse_json, useFormAction } from '../../use_form_action';
import { ErrorAlert, StatusMessage } from '../common/alerts';

/**
 * Imports a curriculum file (the format GET /api/curricula/{id}/export downloads) as a new
 * curriculum. The file text goes to the server as it is, after a local check that it is JSON at
 * all; the server checks the rest and names the path of the first problem, or refuses a name in use.
 */
export function CurriculumImport({ on_imported }: { on_imported: () => void }) {
  const [file, set_file] = useState<File | null>(null);
  // Changed after an import to give a fresh, empty file input.
  const [input_generation, set_input_generation] = useState(0);
  const { busy, error, status, run, clear } = useFormAction();

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    if (!file) return;
    await run(async () => {
      // An editor's byte-order mark is not part of the JSON.
      const definition = parse_json((await file.text()).replace(/^\uFEFF/, ''));
      // The body is the curriculum definition itself, as in the file; the answer wraps it.
      const created = await api.import_curriculum(definition);
      set_file(null);
      set_input_generation((g) => g + 1);
      on_imported();
      return `Imported “${created.name}”.`;
    }, 'Could not import the curriculum');
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
          clear();
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
