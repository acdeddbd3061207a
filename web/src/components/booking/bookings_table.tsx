import { useState } from 'react';
import { api, type Booking, type User } from '../../api';
import { format_date, format_time, format_time_range } from '../../time';
import { error_text } from '../../use_resource';
import { ErrorAlert, StatusMessage } from '../common/alerts';
import { DataTable } from '../common/data_table';

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
      <DataTable<Booking>
        rows={bookings}
        row_key={(b) => b.id}
        row_class={(b) => (b.status === 'cancelled' ? 'row-cancelled' : undefined)}
        columns={[
          show_trainee && { header: 'Booked by', cell: (b) => b.username },
          { header: 'Station', cell: (b) => b.station_name },
          { header: 'Date', cell: (b) => format_date(b.starts_at) },
          { header: 'Time', cell: (b) => format_time_range(b.starts_at, b.ends_at) },
          {
            header: 'Status',
            cell: (b) => <span className={`badge badge-${b.status}`}>{b.status === 'active' ? 'Active' : 'Cancelled'}</span>,
          },
          {
            header: <span className="visually-hidden">Actions</span>,
            className: 'actions',
            cell: (b) =>
              may_cancel(b) && (
                <button
                  type="button"
                  className="button-danger button-small"
                  disabled={busy_id === b.id}
                  aria-label={`Cancel booking at ${b.station_name} on ${format_date(b.starts_at)} ${format_time(b.starts_at)}`}
                  onClick={() => cancel(b)}
                >
                  Cancel
                </button>
              ),
          },
        ]}
      />
    </>
  );
}
