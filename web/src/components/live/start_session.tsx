import { useEffect, useRef, useState, type ReactNode, type SubmitEvent } from 'react';
import { api, type Booking, type Station, type StationTask } from '../../api';
import { navigate } from '../../router';
import { format_time, format_time_range, localize_utc_times, to_api_time } from '../../time';
import { useNow } from '../../use_now';
import { error_text, useResource } from '../../use_resource';
import { ErrorAlert } from '../common/alerts';

const kQuarterHourMs = 15 * 60 * 1000;
const kWalkUpMinutes = [30, 60];

/** A "Start session" form for each of `bookings` that covers the present moment (the server says
 * which: `covers_now`); without one, a walk-up form that books the slot in progress. `bookings` is
 * null while they load: then neither shows, so that the walk-up form does not flash up before a
 * booking that covers now. Slots begin and end on quarter hours: at each, `reload` asks again. */
export function StartSession({ bookings, reload }: { bookings: Booking[] | null; reload: () => void }) {
  const now = useNow(15_000);
  const stations = useResource(['stations'], api.stations);
  const quarter = Math.floor(now / kQuarterHourMs);
  const asked_in = useRef(quarter);
  useEffect(() => {
    if (quarter !== asked_in.current) {
      asked_in.current = quarter;
      reload();
    }
  }, [quarter, reload]);
  if (bookings === null) {
    return (
      <p className="muted" role="status">
        Loading your bookings…
      </p>
    );
  }
  const current = bookings.filter((b) => b.covers_now);

  if (current.length === 0) {
    return <WalkUp stations={stations.data ?? []} now={now} on_booked={reload} />;
  }
  return (
    <>
      {current.map((b) => (
        <StartSessionForm
          key={b.id}
          station_id={b.station_id}
          form_label={`Start a session at ${b.station_name}`}
          heading={
            <>
              <strong>{b.station_name}</strong>, booked {format_time_range(b.starts_at, b.ends_at)}
            </>
          }
          station={stations.data?.find((s) => s.id === b.station_id)}
        />
      ))}
    </>
  );
}

/**
 * Staff run a task at any station in service, with no booking: to try it, to show it, or to record
 * an expert run for the task's benchmark (the experts' band beside every attempt).
 */
export function StaffStartSession() {
  const stations = useResource(['stations'], api.stations);
  const in_service = (stations.data ?? []).filter((s) => !s.retired);
  const [station_id, set_station_id] = useState('');
  const chosen = in_service.find((s) => String(s.id) === station_id) ?? in_service.find((s) => s.online) ?? in_service[0];
  if (!stations.data) return <p className="muted">Loading the stations…</p>;
  if (!chosen) return <p className="empty">No station is in service.</p>;
  return (
    <>
      <div className="form">
        <label htmlFor="staff-station">Station</label>
        <select id="staff-station" value={chosen.id} onChange={(e) => set_station_id(e.target.value)}>
          {in_service.map((s) => (
            <option key={s.id} value={s.id}>
              {s.online ? s.name : `${s.name} (agent offline)`}
            </option>
          ))}
        </select>
      </div>
      <StartSessionForm
        key={chosen.id}
        station_id={chosen.id}
        form_label={`Run a task at ${chosen.name}`}
        heading={<strong>{chosen.name}</strong>}
        station={chosen}
        expert_option
      />
    </>
  );
}

function StartSessionForm({
  station_id,
  form_label,
  heading,
  station,
  expert_option = false,
}: {
  station_id: number;
  form_label: string;
  heading: ReactNode;
  station: Station | undefined;
  /** Offer "Record as an expert run" (staff only; the server refuses it to trainees). */
  expert_option?: boolean;
}) {
  // The tasks this station can run, each with what locks it for this trainee: the server's rules
  // (curriculum/station_offer.h), which it enforces when the session starts as well.
  const [expert, set_expert] = useState(false);
  const offer = useResource(['stations', station_id, 'tasks'], () => api.station_tasks(station_id));
  const tasks: StationTask[] = offer.data?.tasks ?? [];
  const [task, set_task] = useState('');
  const [error, set_error] = useState<string | null>(null);
  const [busy, set_busy] = useState(false);
  // Until the person picks one, the first task that may start is selected.
  const chosen_task = task || (tasks.find((t) => !t.locked_reason)?.key ?? '');
  const locked_reasons = tasks.map((t) => t.locked_reason).filter((reason) => !!reason);
  const instructions = tasks.find((t) => t.key === chosen_task)?.instructions;

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    set_busy(true);
    set_error(null);
    try {
      const session = await api.start_session(station_id, chosen_task, expert);
      navigate(`/sessions/${session.id}`);
    } catch (reason) {
      // e.g. 409 "station 1 agent is offline": the server's own words tell the person what to do.
      set_error(`Could not start the session: ${error_text(reason)}`);
      set_busy(false);
    }
  }

  return (
    <form onSubmit={on_submit} className="form" aria-label={form_label}>
      <p>
        {heading}
        {station && (
          <>
            {' '}
            <span className={`badge ${station.online ? 'badge-online' : 'badge-offline'}`}>
              {station.online ? 'Agent online' : 'Agent offline'}
            </span>
          </>
        )}
      </p>
      <ErrorAlert message={offer.error && `Could not load the station's tasks: ${offer.error}`} />
      <label htmlFor={`start-task-${station_id}`}>Task</label>
      <select
        id={`start-task-${station_id}`}
        value={chosen_task}
        onChange={(e) => set_task(e.target.value)}
        disabled={tasks.length === 0}
        required
      >
        {tasks.length === 0 && <option value="">{offer.data ? 'No task runs at this station' : 'Loading…'}</option>}
        {tasks.map((t) => (
          <option key={t.key} value={t.key} disabled={!!t.locked_reason}>
            {t.locked_reason ? `${t.name} (locked)` : t.name}
          </option>
        ))}
      </select>
      {locked_reasons.length > 0 && (
        <ul className="hint" aria-label="Prerequisites to master first">
          {locked_reasons.map((reason) => (
            <li key={reason}>{reason.charAt(0).toUpperCase() + reason.slice(1)}.</li>
          ))}
        </ul>
      )}
      {instructions && <p className="hint">{instructions}</p>}
      {expert_option && (
        <label className="checkbox-option">
          <input type="checkbox" data-testid="start-expert" checked={expert} onChange={(e) => set_expert(e.target.checked)} /> Record
          as an expert run (its scores join the task's benchmark)
        </label>
      )}
      <ErrorAlert message={error} />
      <button type="submit" className="button-primary" disabled={busy || !chosen_task}>
        {busy ? 'Starting…' : 'Start session'}
      </button>
    </form>
  );
}

/**
 * No booking covers now: offer the slot in progress (from the current quarter hour) at a station
 * whose agent is online, so that a trainee who walks up to a free station can train at once.
 */
function WalkUp({ stations, now, on_booked }: { stations: Station[]; now: number; on_booked: () => void }) {
  const online = stations.filter((s) => s.online);
  const [station_id, set_station_id] = useState('');
  const [minutes, set_minutes] = useState(30);
  const [error, set_error] = useState<string | null>(null);
  const [busy, set_busy] = useState(false);
  const chosen = station_id || String(online[0]?.id ?? '');
  const starts = new Date(Math.floor(now / kQuarterHourMs) * kQuarterHourMs);
  const ends = new Date(starts.getTime() + minutes * 60 * 1000);

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    set_busy(true);
    set_error(null);
    try {
      await api.create_booking(Number(chosen), to_api_time(starts), to_api_time(ends));
      on_booked();
    } catch (reason) {
      // e.g. 409 "Station 1 is already booked from ...": someone else has the station now.
      set_error(`Could not book the station: ${localize_utc_times(error_text(reason))}`);
    } finally {
      set_busy(false);
    }
  }

  if (online.length === 0) {
    return (
      <p className="empty">
        None of your bookings covers the present time, and no station is online to walk up to. Book a slot below.
      </p>
    );
  }
  return (
    <form onSubmit={on_submit} className="form" aria-label="Walk up to a station">
      <p>None of your bookings covers the present time. A free station can be booked from now:</p>
      <label htmlFor="walk-up-station">Station</label>
      <select id="walk-up-station" value={chosen} onChange={(e) => set_station_id(e.target.value)}>
        {online.map((s) => (
          <option key={s.id} value={s.id}>
            {s.name}
          </option>
        ))}
      </select>
      <label htmlFor="walk-up-minutes">Until</label>
      <select id="walk-up-minutes" value={minutes} onChange={(e) => set_minutes(Number(e.target.value))}>
        {kWalkUpMinutes.map((m) => (
          <option key={m} value={m}>
            {format_time(new Date(starts.getTime() + m * 60 * 1000))}
          </option>
        ))}
      </select>
      <ErrorAlert message={error} />
      <button type="submit" className="button-primary" disabled={busy || !chosen}>
        {busy ? 'Booking…' : `Book from ${format_time(starts)}`}
      </button>
    </form>
  );
}
