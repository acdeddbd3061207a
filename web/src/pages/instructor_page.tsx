import { api } from '../api';
import { useUser } from '../auth';
import { BookingsTable } from '../components/bookings_table';
import { RecordingsTable } from '../components/recordings_table';
import { ResourceView } from '../components/resource_view';
import { ScoresTable } from '../components/scores_table';
import { SessionsTable } from '../components/sessions_table';
import { useResource } from '../use_resource';

export function InstructorPage() {
  const user = useUser();
  const sessions = useResource(api.sessions);
  const scores = useResource(api.scores);
  const bookings = useResource(api.bookings);
  const recordings = useResource(api.recordings);

  return (
    <main className="page">
      <h1>Sessions &amp; bookings</h1>
      <section className="card" aria-labelledby="sessions-title">
        <h2 id="sessions-title">Trainees' sessions</h2>
        <ResourceView resource={sessions} what="sessions" empty="No sessions yet.">
          {(data) => <SessionsTable sessions={data} show_trainee />}
        </ResourceView>
      </section>
      <section className="card" aria-labelledby="scores-title">
        <h2 id="scores-title">Scores</h2>
        <ResourceView resource={scores} what="scores" empty="No scores yet.">
          {(data) => <ScoresTable scores={data} show_trainee />}
        </ResourceView>
      </section>
      <section className="card" aria-labelledby="recordings-title">
        <h2 id="recordings-title">Recordings</h2>
        <ResourceView resource={recordings} what="recordings" empty="No recordings yet.">
          {(data) => <RecordingsTable recordings={data} show_trainee />}
        </ResourceView>
      </section>
      <section className="card" aria-labelledby="bookings-title">
        <h2 id="bookings-title">All bookings</h2>
        <ResourceView resource={bookings} what="bookings" empty="No bookings yet.">
          {(data) => <BookingsTable bookings={data} viewer={user} show_trainee on_changed={bookings.reload} />}
        </ResourceView>
      </section>
    </main>
  );
}
