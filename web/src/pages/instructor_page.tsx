import { api } from '../api';
import { useUser } from '../auth';
import { BookingsTable } from '../components/bookings_table';
import { Card } from '../components/card';
import { LiveNow } from '../components/live_now';
import { ProgressOverview } from '../components/progress_overview';
import { ResourceView } from '../components/resource_view';
import { TrainingRecord } from '../components/training_record';
import { useResource } from '../use_resource';

export function InstructorPage() {
  const user = useUser();
  const bookings = useResource(api.bookings);
  const overview = useResource(api.progress_overview);

  return (
    <main className="page">
      <h1>Sessions &amp; bookings</h1>
      <Card id="live-now" title="Live now">
        <LiveNow />
      </Card>
      <Card id="overview" title="Trainees at a glance">
        <ResourceView resource={overview} what="progress" empty="No trainees yet.">
          {(data) => <ProgressOverview trainees={data} />}
        </ResourceView>
      </Card>
      <TrainingRecord whose="everyone" />
      <Card id="bookings" title="All bookings">
        <ResourceView resource={bookings} what="bookings" empty="No bookings yet.">
          {(data) => <BookingsTable bookings={data} viewer={user} show_trainee on_changed={bookings.reload} />}
        </ResourceView>
      </Card>
    </main>
  );
}
