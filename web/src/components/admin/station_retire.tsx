import { api, type Station } from '../../api';
import { useFormAction } from '../../use_form_action';
import { ErrorAlert } from '../common/alerts';

/**
 * Retires a station (kept for its history, no longer booked, started or connected to) or returns
 * it to service. The server refuses while a session runs there or bookings lie ahead, and says
 * which; that message shows here.
 */
export function StationRetire({ station, on_changed }: { station: Station; on_changed: () => void }) {
  const { busy, error, run } = useFormAction();
  return (
    <>
      <button
        type="button"
        className={station.retired ? 'button-small' : 'button-small button-danger'}
        disabled={busy}
        data-testid={`station-${station.id}-retire`}
        onClick={() =>
          void run(async () => {
            await api.update_station(station.id, { retired: !station.retired });
            on_changed();
            return undefined;
          }, `Could not ${station.retired ? 'return' : 'retire'} ${station.name}`)
        }
      >
        {station.retired ? 'Return to service' : 'Retire'}
      </button>
      <ErrorAlert message={error} />
    </>
  );
}
