import { useState, type SubmitEvent } from 'react';
import { api, type Booking } from '../../api';
import {
  format_date,
  format_duration,
  format_time,
  format_time_range,
  local_date,
  local_slot,
  localize_utc_times,
  quarter_hours,
  to_api_time,
  tomorrow,
} from '../../time';
import { error_text, useResource } from '../../use_resource';
import { ErrorAlert, StatusMessage } from '../common/alerts';

const durations = [15, 30, 45, 60, 90, 120];
const start_times = quarter_hours();

/** Books a slot for the logged-in user; times are entered in local time and sent as UTC. */
export function BookingForm({ on_booked }: { on_booked: (booking: Booking) => void }) {
  const all_stations = useResource(['stations'], api.stations);
  // A retired station is listed for its history, never offered for booking (the server refuses).
  const stations = { ...all_stations, data: all_stations.data?.filter((s) => !s.retired) ?? null };
  const [station_id, set_station_id] = useState('');
  const [date, set_date] = useState(tomorrow);
  const [start, set_start] = useState('09:00');
  const [minutes, set_minutes] = useState(60);
  const [error, set_error] = useState<string | null>(null);
  const [status, set_status] = useState<string | null>(null);
  const [busy, set_busy] = useState(false);

  // Until the person picks one, the first station is selected.
  const chosen_station = station_id || String(stations.data?.[0]?.id ?? '');
  const selected = stations.data?.find((s) => String(s.id) === chosen_station);
  const slot = local_slot(date, start, minutes);

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    set_error(null);
    set_status(null);
    if (!chosen_station) return set_error('Choose a station.');
    if (!slot) return set_error('Enter a valid date and start time.');
    set_busy(true);
    try {
      const booking = await api.create_booking(Number(chosen_station), to_api_time(slot.starts), to_api_time(slot.ends));
      set_status(
        `Booked ${booking.station_name} on ${format_date(booking.starts_at)}, ` +
          `${format_time_range(booking.starts_at, booking.ends_at)}.`,
      );
      on_booked(booking);
    } catch (reason) {
      // A conflict names the other booking's times in UTC; the person thinks in local time.
      set_error(`Could not book the slot: ${localize_utc_times(error_text(reason))}`);
    } finally {
      set_busy(false);
    }
  }

  return (
    <form onSubmit={on_submit} className="form" aria-label="Book a slot">
      <ErrorAlert message={stations.error && `Could not load stations: ${stations.error}`} />
      <label htmlFor="booking-station">Station</label>
      <select
        id="booking-station"
        value={chosen_station}
        onChange={(e) => set_station_id(e.target.value)}
        disabled={!stations.data || stations.data.length === 0}
        required
      >
        {stations.loading && !stations.data && <option value="">Loading stations…</option>}
        {stations.data?.length === 0 && <option value="">No stations yet</option>}
        {stations.data?.map((s) => (
          <option key={s.id} value={s.id}>
            {s.name} — {s.online ? 'online' : 'offline'}
          </option>
        ))}
      </select>
      {selected?.location && <p className="hint">Location: {selected.location}</p>}

      <div className="form-row">
        <div>
          <label htmlFor="booking-date">Date</label>
          <input
            id="booking-date"
            type="date"
            min={local_date(new Date())}
            required
            value={date}
            onChange={(e) => set_date(e.target.value)}
          />
        </div>
        <div>
          <label htmlFor="booking-start">Start time</label>
          <select id="booking-start" value={start} onChange={(e) => set_start(e.target.value)}>
            {start_times.map((t) => (
              <option key={t} value={t}>
                {t}
              </option>
            ))}
          </select>
        </div>
        <div>
          <label htmlFor="booking-duration">Duration</label>
          <select id="booking-duration" value={minutes} onChange={(e) => set_minutes(Number(e.target.value))}>
            {durations.map((d) => (
              <option key={d} value={d}>
                {format_duration(d)}
              </option>
            ))}
          </select>
        </div>
      </div>
      <p className="hint">
        {slot ? `Ends at ${format_time(slot.ends)}${local_date(slot.ends) === date ? '' : ` on ${format_date(slot.ends)}`}` : 'Pick a date.'}
        {' · '}times are in your local time zone
      </p>

      <ErrorAlert message={error} />
      <StatusMessage message={status} />
      <button type="submit" className="button-primary" disabled={busy || !chosen_station}>
        {busy ? 'Booking…' : 'Book slot'}
      </button>
    </form>
  );
}
