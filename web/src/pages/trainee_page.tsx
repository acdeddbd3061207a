import { api } from '../api';
import { BookingCalendar } from '../components/booking/booking_calendar';
import { ProgressChart } from '../components/training/progress_chart';
import { useUser } from '../auth';
import { BookingForm } from '../components/booking/booking_form';
import { BookingsTable } from '../components/booking/bookings_table';
import { Card } from '../components/common/card';
import { CurriculumProgress } from '../components/training/curriculum_progress';
import { ResourceView } from '../components/common/resource_view';
import { StartSession } from '../components/live/start_session';
import { TrainingRecord } from '../components/training/training_record';
import { useResource } from '../use_resource';
import { usePageTitle } from '../use_page_title';

export function TraineePage() {
  usePageTitle('My training');
  const user = useUser();
  // Shared by the start form (today's bookings), the booking form (reload) and the list.
  const bookings = useResource(['bookings'], api.bookings);
  const progress = useResource(['progress'], api.progress);
  const stations = useResource(['stations'], api.stations);
  const scores = useResource(['scores'], api.scores);
  const curricula = useResource(['curricula'], api.curricula);
  const benchmarks = useResource(['benchmarks'], api.benchmarks);

  return (
    <main id="main" tabIndex={-1} className="page">
      <h1>My training</h1>
      <Card id="train" title="Train now">
        <StartSession bookings={bookings.data} reload={bookings.reload} />
      </Card>
      <div className="columns">
        <Card id="book" title="Book a slot">
          <BookingForm on_booked={bookings.reload} />
        </Card>
        <Card id="bookings" title="My bookings" grow>
          <ResourceView resource={bookings} what="bookings" empty="You have no bookings yet. Book a slot to start training.">
            {(data) => <BookingsTable bookings={data} viewer={user} show_trainee={false} on_changed={bookings.reload} />}
          </ResourceView>
        </Card>
      </div>
      <Card id="calendar" title="Station calendar">
        {stations.data && (
          <BookingCalendar stations={stations.data.filter((s) => !s.retired)} viewer={user} on_changed={bookings.reload} reload_on={bookings.data} />
        )}
      </Card>
      <Card id="curriculum" title="My curriculum">
        {progress.error && <p role="alert">Could not load your progress: {progress.error}</p>}
        {progress.data && <CurriculumProgress progress={progress.data} />}
      </Card>
      <Card id="progress" title="My progress over attempts">
        {scores.data && curricula.data && benchmarks.data && (
          <ProgressChart scores={scores.data} curricula={curricula.data} benchmarks={benchmarks.data} />
        )}
      </Card>
      <TrainingRecord whose="own" />
    </main>
  );
}
