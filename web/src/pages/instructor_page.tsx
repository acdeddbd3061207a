import { api } from '../api';
import { useUser } from '../auth';
import { BookingsTable } from '../components/booking/bookings_table';
import { Card } from '../components/common/card';
import { LiveNow } from '../components/live/live_now';
import { StaffStartSession } from '../components/live/start_session';
import { ProgressOverview } from '../components/training/progress_overview';
import { ResourceView } from '../components/common/resource_view';
import { TrainingRecord } from '../components/training/training_record';
import { useResource } from '../use_resource';
import { usePageTitle } from '../use_page_title';

export function InstructorPage() {
  usePageTitle('Sessions & bookings');
  const user = useUser();
  const bookings = useResource(['bookings'], api.bookings);
  const overview = useResource(['trainees', 'progress'], api.progress_overview);

  return (
    <main id="main" tabIndex={-1} className="page">
      <h1>Sessions &amp; bookings</h1>
      <Card id="live-now" title="Live now">
        <LiveNow />
      </Card>
      <Card id="run-task" title="Run a task">
        <StaffStartSession />
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
