import { useState, type SubmitEvent } from 'react';
import { api, type Station } from '../../api';
import { useFormAction } from '../../use_form_action';
import { ErrorAlert } from '../common/alerts';

/** Creates a station and shows its agent token, which the server reveals only this once. */
export function StationForm({ on_created }: { on_created: (station: Station) => void }) {
  const [name, set_name] = useState('');
  const [location, set_location] = useState('');
  const [kind, set_kind] = useState('');
  const { busy, error, run, set_error } = useFormAction();
  const [created, set_created] = useState<{ station: Station; token: string } | null>(null);
  const [copied, set_copied] = useState(false);

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    await run(async () => {
      const result = await api.create_station(name.trim(), location.trim(), kind.trim());
      set_created(result);
      set_copied(false);
      set_name('');
      set_location('');
      set_kind('');
      on_created(result.station);
    }, 'Could not create the station');
  }

  async function copy_token(token: string) {
    try {
      await navigator.clipboard.writeText(token);
      set_copied(true);
    } catch {
      set_error('Could not copy automatically: select the token and copy it by hand.');
    }
  }

  return (
    <>
      {created && (
        <div className="token-panel" role="region" aria-label="New station token">
          <h3>Station token for {created.station.name}</h3>
          <p>
            <strong>This token is shown only once.</strong> Copy it now and configure the station's agent with it;
            it cannot be displayed again.
          </p>
          <code className="token" aria-label="Station token">
            {created.token}
          </code>
          <div className="button-row">
            <button type="button" className="button-primary" onClick={() => copy_token(created.token)}>
              {copied ? 'Copied' : 'Copy token'}
            </button>
            <button type="button" className="button-quiet" onClick={() => set_created(null)}>
              I have saved the token
            </button>
          </div>
        </div>
      )}
      <form onSubmit={on_submit} className="form" aria-label="Create station">
        <label htmlFor="station-name">Station name</label>
        <input id="station-name" required value={name} onChange={(e) => set_name(e.target.value)} />
        <label htmlFor="station-location">Location</label>
        <input id="station-location" value={location} onChange={(e) => set_location(e.target.value)} />
        <label htmlFor="station-kind">Kind</label>
        <input
          id="station-kind"
          value={kind}
          onChange={(e) => set_kind(e.target.value)}
          list="station-kinds"
          placeholder="e.g. laparoscopy"
          aria-describedby="station-kind-hint"
        />
        <p id="station-kind-hint" className="hint">
          What its devices and scenes can run: the curriculum's tasks name the kind of station they need.
        </p>
        <ErrorAlert message={error} />
        <button type="submit" className="button-primary" disabled={busy}>
          {busy ? 'Creating…' : 'Create station'}
        </button>
      </form>
    </>
  );
}

/** The kinds the curricula's tasks ask for, offered when a station's kind is set. */
export function StationKindOptions({ kinds }: { kinds: string[] }) {
  return (
    <datalist id="station-kinds">
      {kinds.map((k) => (
        <option key={k} value={k} />
      ))}
    </datalist>
  );
}

/** Sets what a station can run (PATCH /api/stations/{id}); the server audits the change. */
export function StationKindPicker({
  station,
  kinds,
  on_changed,
}: {
  station: Station;
  kinds: string[];
  on_changed: () => void;
}) {
  const { busy, error, run } = useFormAction();
  const options = kinds.includes(station.kind) || !station.kind ? kinds : [station.kind, ...kinds];
  return (
    <>
      <select
        aria-label={`Kind of ${station.name}`}
        value={station.kind}
        disabled={busy}
        onChange={(e) => {
          const kind = e.target.value;
          void run(async () => {
            await api.set_station_kind(station.id, kind);
            on_changed();
          }, `Could not change ${station.name}`);
        }}
      >
        <option value="">Not declared</option>
        {options.map((k) => (
          <option key={k} value={k}>
            {k}
          </option>
        ))}
      </select>
      <ErrorAlert message={error} />
    </>
  );
}
