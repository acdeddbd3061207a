// Times travel as UTC ISO strings with whole seconds ("2026-11-21T14:00:00Z", docs/api.md) and are
// shown in the browser's local time zone.

const date_format = new Intl.DateTimeFormat(undefined, {
  weekday: 'short',
  day: 'numeric',
  month: 'short',
  year: 'numeric',
});
const time_format = new Intl.DateTimeFormat(undefined, { hour: '2-digit', minute: '2-digit' });

export function format_date(time: string | Date): string {
  return date_format.format(new Date(time));
}

export function format_time(time: string | Date): string {
  return time_format.format(new Date(time));
}

export function format_date_time(iso: string | null): string {
  if (iso === null) return '—';
  return `${format_date(iso)}, ${format_time(iso)}`;
}

/** "10:00–11:30", with the end's date added when the slot crosses midnight. */
export function format_time_range(starts_at: string, ends_at: string): string {
  const same_day = local_date(new Date(starts_at)) === local_date(new Date(ends_at));
  const end = same_day ? format_time(ends_at) : `${format_time(ends_at)} (${format_date(ends_at)})`;
  return `${format_time(starts_at)}–${end}`;
}

/** `date` as "YYYY-MM-DD" in local time, the format of <input type="date">. */
export function local_date(date: Date): string {
  const pad = (n: number) => String(n).padStart(2, '0');
  return `${date.getFullYear()}-${pad(date.getMonth() + 1)}-${pad(date.getDate())}`;
}

export function tomorrow(): string {
  const date = new Date();
  date.setDate(date.getDate() + 1);
  return local_date(date);
}

/** "00:00", "00:15", ... "23:45". */
export function quarter_hours(): string[] {
  const times: string[] = [];
  for (let minutes = 0; minutes < 24 * 60; minutes += 15) {
    times.push(`${String(Math.floor(minutes / 60)).padStart(2, '0')}:${String(minutes % 60).padStart(2, '0')}`);
  }
  return times;
}

export function to_api_time(date: Date): string {
  return date.toISOString().replace(/\.\d{3}Z$/, 'Z');
}

/**
 * The slot starting at local `date` ("YYYY-MM-DD") and `time` ("HH:MM") and lasting `minutes`,
 * or null when the date or time is not valid.
 */
export function local_slot(date: string, time: string, minutes: number): { starts: Date; ends: Date } | null {
  const match_date = /^(\d{4})-(\d{2})-(\d{2})$/.exec(date);
  const match_time = /^(\d{2}):(\d{2})$/.exec(time);
  if (!match_date || !match_time) return null;
  const [, year, month, day] = match_date.map(Number) as [number, number, number, number];
  const [, hour, minute] = match_time.map(Number) as [number, number, number];
  const starts = new Date(year, month - 1, day, hour, minute);
  if (Number.isNaN(starts.getTime())) return null;
  return { starts, ends: new Date(starts.getTime() + minutes * 60_000) };
}

export function format_duration(minutes: number): string {
  if (minutes < 60) return `${minutes} min`;
  const hours = Math.floor(minutes / 60);
  const rest = minutes % 60;
  return rest === 0 ? `${hours} h` : `${hours} h ${rest} min`;
}

const utc_time_pattern = /\b\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}Z\b/g;

/**
 * Rewrites the UTC times inside a server message (e.g. a booking conflict) in local time; a time
 * on the same local day as the one before it is shown without its date ("from ..., 10:00 to 11:00").
 */
export function localize_utc_times(message: string): string {
  let previous_day: string | null = null;
  return message.replace(utc_time_pattern, (iso) => {
    const day = local_date(new Date(iso));
    const text = day === previous_day ? format_time(iso) : format_date_time(iso);
    previous_day = day;
    return text;
  });
}
