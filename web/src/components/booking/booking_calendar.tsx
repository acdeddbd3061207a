import { useEffect, useState } from 'react';
import { api, type ScheduleEntry, type Station, type User } from '../../api';
import { format_date, localize_utc_times, to_api_time } from '../../time';
import { useNow } from '../../use_now';
import { error_text } from '../../use_resource';
import { ErrorAlert, StatusMessage } from '../common/alerts';

const first_hour = 8;
const last_hour = 20;
const slot_minutes = 30;
const rows = Array.from({ length: ((last_hour - first_hour) * 60) / slot_minutes }, (_, i) => i);
const days = [0, 1, 2, 3, 4, 5, 6];

const weekday_format = new Intl.DateTimeFormat(undefined, { weekday: 'long' });
const day_format = new Intl.DateTimeFormat(undefined, { weekday: 'short', day: 'numeric', month: 'short' });

/** "HH:MM" on the 24-hour clock, the same in every locale so that button names are predictable. */
function hh_mm(date: Date): string {
  return `${String(date.getHours()).padStart(2, '0')}:${String(date.getMinutes()).padStart(2, '0')}`;
}

/** Local midnight of the Monday of `date`'s week. */
function monday_of(date: Date): Date {
  const days_since_monday = (date.getDay() + 6) % 7;
  return new Date(date.getFullYear(), date.getMonth(), date.getDate() - days_since_monday);
}

/** `date` moved by whole local days; built from the calendar date so daylight-saving changes don't shift it. */
function add_days(date: Date, n: number): Date {
  return new Date(date.getFullYear(), date.getMonth(), date.getDate() + n);
}

/** Start of the row's slot on the given day, in local time. */
function slot_start(day: Date, row: number): Date {
  const minutes = first_hour * 60 + row * slot_minutes;
  return new Date(day.getFullYear(), day.getMonth(), day.getDate(), Math.floor(minutes / 60), minutes % 60);
}

interface Parsed {
  booking: ScheduleEntry;
  starts: number;
  ends: number;
}

/**
 * A week of one station's half-hour slots from 08:00 to 20:00 local time, Monday first, from the
 * station's schedule: free slots have a Book button, the viewer's own bookings a Cancel button,
 * other people's bookings are "Taken" (staff see who booked). A booking the server refuses, e.g.
 * because someone took the slot since the calendar was loaded, is explained in an alert above the
 * grid, and the calendar reloads to show why.
 */
export function BookingCalendar({
  stations,
  viewer,
  on_changed,
  reload_on,
}: {
  stations: Station[];
  viewer: User;
  /** Called after a booking was made or cancelled, e.g. to reload a list of bookings. */
  on_changed: () => void;
  /** The calendar reloads whenever this changes, e.g. the page's list of bookings. */
  reload_on?: unknown;
}) {
  const [chosen_station, set_station] = useState('');
  const [week, set_week] = useState(() => monday_of(new Date()));
  const [busy, set_busy] = useState<string | null>(null);
  const [error, set_error] = useState<string | null>(null);
  const [status, set_status] = useState<string | null>(null);
  // The schedule with the station it belongs to, so that another station's never shows.
  const [schedule, set_schedule] = useState<{ station_id: number; entries: ScheduleEntry[] } | null>(null);
  const [load_error, set_load_error] = useState<string | null>(null);
  const [generation, set_generation] = useState(0);
  const now = useNow(30_000);
  // Until the person picks one, the first station is shown.
  const found = stations.find((s) => String(s.id) === chosen_station) ?? stations[0];
  const station_id = found?.id;

  useEffect(() => {
    if (station_id === undefined) return;
    let current = true;
    api.station_schedule(station_id).then(
      (entries) => {
        if (!current) return;
        set_schedule({ station_id, entries });
        set_load_error(null);
      },
      (reason: unknown) => current && set_load_error(`Could not load the station's bookings: ${error_text(reason)}`),
    );
    return () => {
      current = false;
    };
  }, [station_id, generation, reload_on]);

  if (!found) return <p className="empty">No stations yet.</p>;
  const station: Station = found;
  const staff = viewer.role !== 'trainee';
  // Until the station's schedule is in, no slot can be booked: it may be taken.
  const loading = schedule?.station_id !== station.id;
  const entries = loading ? [] : schedule.entries;
  const active: Parsed[] = entries.map((b) => ({ booking: b, starts: Date.parse(b.starts_at), ends: Date.parse(b.ends_at) }));
  const week_days = days.map((d) => add_days(week, d));

  async function run(key: string, action: () => Promise<void>, done: string, failed: string) {
    set_busy(key);
    set_error(null);
    set_status(null);
    try {
      await action();
      set_status(done);
      on_changed();
    } catch (reason) {
      // A conflict names the other booking's times in UTC; the person thinks in local time.
      set_error(`${failed}: ${localize_utc_times(error_text(reason))}`);
    } finally {
      set_busy(null);
      set_generation((g) => g + 1);
    }
  }

  function book(starts: Date, ends: Date, what: string) {
    const action = async () => {
      await api.create_booking(station.id, to_api_time(starts), to_api_time(ends));
    };
    void run(`book-${starts.getTime()}`, action, `Booked ${what}.`, 'Could not book the slot');
  }

  function cancel(booking: ScheduleEntry, what: string) {
    const id = booking.id;
    if (id === null) return;
    void run(`cancel-${id}`, () => api.cancel_booking(id), `Cancelled ${what}.`, 'Could not cancel the booking');
  }

  function cell(day: Date, row: number) {
    const starts = slot_start(day, row);
    const ends = new Date(starts.getTime() + slot_minutes * 60_000);
    const key = to_api_time(starts);
    const weekday = weekday_format.format(starts);
    const past = starts.getTime() < now;
    const hit = active.find((p) => p.starts < ends.getTime() && p.ends > starts.getTime());
    const test_id = `slot-${station.id}-${key}`;

    if (hit) {
      const b = hit.booking;
      const mine = b.mine;
      // A booking over several rows carries its Cancel button in its first row of the day.
      const first_row = hit.starts >= starts.getTime() || row === 0;
      const b_start = new Date(hit.starts);
      const what = `${station.name} ${weekday_format.format(b_start)} ${hh_mm(b_start)}`;
      return (
        <td key={key} data-testid={test_id} className={mine ? 'slot slot-mine' : 'slot slot-taken'}>
          {mine ? (
            <>
              <span>Mine</span>
              {first_row && hit.ends > now && (
                <button
                  type="button"
                  className="button-danger button-small slot-cancel"
                  aria-label={`Cancel my booking ${what}`}
                  disabled={busy !== null}
                  onClick={() => cancel(b, `your booking ${what}`)}
                >
                  {busy === `cancel-${b.id}` ? '…' : 'Cancel'}
                </button>
              )}
            </>
          ) : staff ? (
            <span title={b.username ?? undefined}>
              <span className="visually-hidden">Taken by </span>
              {b.username}
            </span>
          ) : (
            <span>Taken</span>
          )}
        </td>
      );
    }

    const label = `Book ${station.name} ${weekday} ${hh_mm(starts)}-${hh_mm(ends)}`;
    return (
      <td key={key} data-testid={test_id} className={past ? 'slot slot-past' : 'slot slot-free'}>
        <button
          type="button"
          className="slot-book"
          aria-label={label}
          title={past ? 'This slot has passed' : undefined}
          disabled={past || busy !== null || loading}
          onClick={() => book(starts, ends, `${station.name} ${weekday} ${hh_mm(starts)}-${hh_mm(ends)}`)}
        >
          {busy === `book-${starts.getTime()}` ? 'Booking…' : past ? '' : 'Book'}
        </button>
      </td>
    );
  }

  const today = monday_of(new Date()).getTime() === week.getTime() ? new Date().getDay() : null;
  const week_label = `${format_date(week)} – ${format_date(add_days(week, 6))}`;

  return (
    <div className="booking-calendar" data-testid="booking-calendar">
      <div className="calendar-toolbar">
        <label htmlFor="calendar-station">Station</label>
        <select id="calendar-station" value={String(station.id)} onChange={(e) => set_station(e.target.value)}>
          {stations.map((s) => (
            <option key={s.id} value={s.id}>
              {s.name} — {s.online ? 'online' : 'offline'}
            </option>
          ))}
        </select>
        <div className="calendar-week-buttons">
          <button type="button" className="button-quiet button-small" onClick={() => set_week(add_days(week, -7))}>
            Previous week
          </button>
          <button type="button" className="button-quiet button-small" onClick={() => set_week(monday_of(new Date()))}>
            This week
          </button>
          <button type="button" className="button-quiet button-small" onClick={() => set_week(add_days(week, 7))}>
            Next week
          </button>
        </div>
        <span className="calendar-week" aria-live="polite">
          {week_label}
        </span>
      </div>
      <ErrorAlert message={load_error} />
      <ErrorAlert message={error} />
      <StatusMessage message={status} />
      <div className="table-wrap">
        <table className="calendar-grid">
          <caption className="visually-hidden">{`Slots of ${station.name}, ${week_label}, local time`}</caption>
          <thead>
            <tr>
              <th scope="col" className="calendar-time">
                Time
              </th>
              {week_days.map((d) => (
                <th key={d.getTime()} scope="col" className={d.getDay() === today ? 'calendar-today' : undefined}>
                  {day_format.format(d)}
                </th>
              ))}
            </tr>
          </thead>
          <tbody>
            {rows.map((row) => (
              <tr key={row}>
                <th scope="row" className="calendar-time">
                  {hh_mm(slot_start(week, row))}
                </th>
                {week_days.map((d) => cell(d, row))}
              </tr>
            ))}
          </tbody>
        </table>
      </div>
    </div>
  );
}
