import { useEffect, useState, type SubmitEvent } from 'react';
import { api, type CalibrationAnswer, type Station } from '../../api';
import { error_text } from '../../use_resource';
import { parse_json, useFormAction } from '../../use_form_action';
import { ErrorAlert, StatusMessage } from '../common/alerts';
import { CalibrationFields } from './calibration_fields';

/**
 * A station's calibration (device-to-scene mappings, docs/api.md "Calibration") as a form, with
 * the JSON text kept for power users. The server validates what is saved and names the path of the first problem; it refuses
 * (409) while a session runs at the station, since remapping a hand in use would move its tool.
 */
export function CalibrationEditor({ stations }: { stations: Station[] }) {
  const [station_id, set_station_id] = useState<number | null>(stations[0]?.id ?? null);
  const [answer, set_answer] = useState<CalibrationAnswer | null>(null);
  const [text, set_text] = useState('');
  const [load_error, set_load_error] = useState<string | null>(null);
  const { busy, error, status, run, clear } = useFormAction();

  // The chosen station, or the first one when it is gone from the list (or none was chosen yet).
  const chosen = stations.find((s) => s.id === station_id) ?? stations[0] ?? null;
  const chosen_id = chosen?.id ?? null;

  function show(loaded: CalibrationAnswer) {
    set_answer(loaded);
    set_text(JSON.stringify(loaded.calibration, null, 2));
  }

  // Another station: nothing of the last one's calibration stays on screen while its own loads.
  const [shown_id, set_shown_id] = useState(chosen_id);
  if (shown_id !== chosen_id) {
    set_shown_id(chosen_id);
    set_answer(null);
    set_text('');
    set_load_error(null);
  }

  useEffect(() => {
    if (chosen_id === null) return;
    let current = true;
    api.calibration(chosen_id).then(
      (loaded) => current && show(loaded),
      (reason: unknown) => current && set_load_error(`Could not load the calibration: ${error_text(reason)}`),
    );
    return () => {
      current = false;
    };
  }, [chosen_id]);

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    if (chosen_id === null) return;
    await run(async () => {
      // The answer holds the calibration as stored (normalised), i.e. what a reload would show.
      show(await api.set_calibration(chosen_id, parse_json(text)));
      return 'Calibration saved.';
    }, 'Could not save the calibration');
  }

  if (chosen === null) {
    return (
      <div data-testid="calibration-editor">
        <p className="empty">No stations yet. Create one to calibrate it.</p>
      </div>
    );
  }
  return (
    <form
      className="form calibration-editor"
      data-testid="calibration-editor"
      aria-label="Station calibration"
      onSubmit={on_submit}
    >
      <label htmlFor="calibration-station">Station</label>
      <select
        id="calibration-station"
        value={chosen.id}
        disabled={busy}
        onChange={(e) => {
          set_station_id(Number(e.target.value));
          clear();
        }}
      >
        {stations.map((s) => (
          <option key={s.id} value={s.id}>
            {s.name}
          </option>
        ))}
      </select>
      <ErrorAlert message={load_error} />
      {!answer && !load_error && <p className="muted" role="status">Loading the calibration…</p>}
      {answer?.default && (
        <p className="hint">Nothing stored for this station yet: this is the default (two pens, identity mappings).</p>
      )}
      {answer && <CalibrationFields text={text} disabled={busy} on_change={set_text} />}
      <details className="power-user">
        <summary>Edit as JSON</summary>
        <textarea
          className="calibration-text"
          aria-label="Calibration JSON"
          spellCheck={false}
          rows={18}
          value={text}
          disabled={!answer}
          onChange={(e) => set_text(e.target.value)}
        />
      </details>
      <ErrorAlert message={error} />
      <StatusMessage message={status} />
      <button type="submit" className="button-primary" disabled={busy || !answer}>
        {busy ? 'Saving…' : 'Save calibration'}
      </button>
    </form>
  );
}
