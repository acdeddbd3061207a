import { useState } from 'react';
import { api, type Booking, type User } from '../api';
import { format_date, format_time, format_time_range } from '../time';
import { error_text } from '../use_resource';
import { ErrorAlert, StatusMessage } from './alerts';

/**
 * Bookings, newest first as the server sends them; cancelled ones stay listed, greyed.
 * `viewer` decides which rows get a Cancel button (the owner's and, for admins, all).
 */
export function BookingsTable({
  bookings,
  viewer,
  show_trainee,
  on_changed,
}: {
  bookings: Booking[];
  viewer: User;
  show_trainee: boolean;
  on_changed: () => void;
}) {
  const [error, set_error] = useState<string | null>(null);
  const [status, set_status] = useState<string | null>(null);
  const [busy_id, set_busy_id] = useState<number | null>(null);

  async function cancel(booking: Booking) {
    const when = `${format_date(booking.starts_at)}, ${format_time_range(booking.starts_at, booking.ends_at)}`;
    if (!window.confirm(`Cancel the booking at ${booking.station_name} on ${when}?`)) return;
    set_busy_id(booking.id);
    set_error(null);
    set_status(null);
    try {
      await api.cancel_booking(booking.id);
      set_status(`Cancelled the booking at ${booking.station_name} on ${when}.`);
    } catch (reason) {
      set_error(`Could not cancel the booking: ${error_text(reason)}`);
    } finally {
      set_busy_id(null);
      on_changed();
    }
  }

  const may_cancel = (b: Booking) => b.status === 'active' && (b.user_id === viewer.id || viewer.role === 'admin');

  return (
    <>
      <ErrorAlert message={error} />
      <StatusMessage message={status} />
      <div className="table-wrap">
        <table>
          <thead>
            <tr>
              {show_trainee && <th scope="col">Booked by</th>}
              <th scope="col">Station</th>
              <th scope="col">Date</th>
              <th scope="col">Time</th>
              <th scope="col">Status</th>
              <th scope="col">
                <span className="visually-hidden">Actions</span>
              </th>
            </tr>
          </thead>
          <tbody>
            {bookings.map((b) => (
              <tr key={b.id} className={b.status === 'cancelled' ? 'row-cancelled' : undefined}>
                {show_trainee && <td>{b.username}</td>}
                <td>{b.station_name}</td>
                <td>{format_date(b.starts_at)}</td>
                <td>{format_time_range(b.starts_at, b.ends_at)}</td>
                <td>
                  <span className={`badge badge-${b.status}`}>{b.status === 'active' ? 'Active' : 'Cancelled'}</span>
                </td>
                <td className="actions">
                  {may_cancel(b) && (
                    <button
                      type="button"
                      className="button-danger button-small"
                      disabled={busy_id === b.id}
                      aria-label={`Cancel booking at ${b.station_name} on ${format_date(b.starts_at)} ${format_time(b.starts_at)}`}
                      onClick={() => cancel(b)}
                    >
                      Cancel
                    </button>
                  )}
                </td>
              </tr>
            ))}
          </tbody>
        </table>
      </div>
    </>
  );
}
