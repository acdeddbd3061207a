import { api } from '../../api';
import { useResource } from '../../use_resource';
import { Card } from '../common/card';
import { RecordingsTable } from '../review/recordings_table';
import { ResourceView } from '../common/resource_view';
import { ScoresTable } from '../review/scores_table';
import { SessionsTable } from './sessions_table';

/** Titles and empty-state messages: a trainee reads about their own training, an instructor about everyone's. */
const text = {
  own: {
    sessions: { title: 'My sessions', empty: 'No sessions yet. They appear here once you train at a station.' },
    scores: { title: 'My scores', empty: 'No scores yet. Each finished session is scored here.' },
    recordings: { title: 'My recordings', empty: 'No recordings yet. Every session you train is recorded.' },
  },
  everyone: {
    sessions: { title: "Trainees' sessions", empty: 'No sessions yet.' },
    scores: { title: 'Scores', empty: 'No scores yet.' },
    recordings: { title: 'Recordings', empty: 'No recordings yet.' },
  },
} as const;

/**
 * The sessions, scores and recordings the viewer may see, one card each. The server already limits
 * them to the viewer's own for a trainee; `whose` only picks the wording and whether a Trainee
 * column is worth showing.
 */
export function TrainingRecord({ whose }: { whose: 'own' | 'everyone' }) {
  const sessions = useResource(['sessions'], api.sessions);
  const scores = useResource(['scores'], api.scores);
  const recordings = useResource(['recordings'], api.recordings);
  const show_trainee = whose === 'everyone';
  const words = text[whose];

  return (
    <>
      <Card id="sessions" title={words.sessions.title}>
        <ResourceView resource={sessions} what="sessions" empty={words.sessions.empty}>
          {(data) => <SessionsTable sessions={data} show_trainee={show_trainee} />}
        </ResourceView>
      </Card>
      <Card id="scores" title={words.scores.title}>
        <ResourceView resource={scores} what="scores" empty={words.scores.empty}>
          {(data) => <ScoresTable scores={data} show_trainee={show_trainee} />}
        </ResourceView>
      </Card>
      <Card id="recordings" title={words.recordings.title}>
        <ResourceView resource={recordings} what="recordings" empty={words.recordings.empty}>
          {(data) => <RecordingsTable recordings={data} show_trainee={show_trainee} />}
        </ResourceView>
      </Card>
    </>
  );
}
