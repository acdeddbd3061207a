import { api } from '../api';
import { useUser } from '../auth';
import { BookingForm } from '../components/booking_form';
import { BookingsTable } from '../components/bookings_table';
import { RecordingsTable } from '../components/recordings_table';
import { ResourceView } from '../components/resource_view';
import { ScoresTable } from '../components/scores_table';
import { SessionsTable } from '../components/sessions_table';
import { StartSession } from '../components/start_session';
import { useResource } from '../use_resource';

export function TraineePage() {
  const user = useUser();
  const bookings = useResource(api.bookings);
  const sessions = useResource(api.sessions);
  const scores = useResource(api.scores);
  const recordings = useResource(api.recordings);

  return (
    <main className="page">
      <h1>My training</h1>
      <section className="card" aria-labelledby="train-title">
        <h2 id="train-title">Train now</h2>
        <StartSession bookings={bookings.data ?? []} />
      </section>
      <div className="columns">
        <section className="card" aria-labelledby="book-title">
          <h2 id="book-title">Book a slot</h2>
          <BookingForm on_booked={bookings.reload} />
        </section>
        <section className="card grow" aria-labelledby="bookings-title">
          <h2 id="bookings-title">My bookings</h2>
          <ResourceView resource={bookings} what="bookings" empty="You have no bookings yet. Book a slot to start training.">
            {(data) => <BookingsTable bookings={data} viewer={user} show_trainee={false} on_changed={bookings.reload} />}
          </ResourceView>
        </section>
      </div>
      <section className="card" aria-labelledby="sessions-title">
        <h2 id="sessions-title">My sessions</h2>
        <ResourceView resource={sessions} what="sessions" empty="No sessions yet. They appear here once you train at a station.">
          {(data) => <SessionsTable sessions={data} show_trainee={false} />}
        </ResourceView>
      </section>
      <section className="card" aria-labelledby="scores-title">
        <h2 id="scores-title">My scores</h2>
        <ResourceView resource={scores} what="scores" empty="No scores yet. Each finished session is scored here.">
          {(data) => <ScoresTable scores={data} show_trainee={false} />}
        </ResourceView>
      </section>
      <section className="card" aria-labelledby="recordings-title">
        <h2 id="recordings-title">My recordings</h2>
        <ResourceView resource={recordings} what="recordings" empty="No recordings yet. Every session you train is recorded.">
          {(data) => <RecordingsTable recordings={data} show_trainee={false} />}
        </ResourceView>
      </section>
    </main>
  );
}
