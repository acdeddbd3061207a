import { useMemo, useState, type SubmitEvent } from 'react';
import { api, type Annotation, type ScoreAdjustment, type User } from '../../api';
import { format_date_time } from '../../time';
import { useFormAction } from '../../use_form_action';
import { useResource } from '../../use_resource';
import { ErrorAlert, StatusMessage } from '../common/alerts';
import { format_seconds } from '../common/format';

/**
 * What instructors add to an attempt: notes at a time of the replay (a click on one jumps there),
 * and a pass or fail that overrides the computed result, with a reason. Trainees read both.
 */
export function ReviewNotes({
  session_id,
  viewer,
  position_s,
  on_seek,
}: {
  session_id: number;
  viewer: User;
  position_s: number;
  on_seek: (t_s: number) => void;
}) {
  const can_write = viewer.role !== 'trainee';
  const load_annotations = useMemo(() => () => api.annotations(session_id), [session_id]);
  const load_adjustments = useMemo(() => () => api.adjustments(session_id), [session_id]);
  const annotations = useResource(['sessions', session_id, 'annotations'], load_annotations);
  const adjustments = useResource(['sessions', session_id, 'adjustments'], load_adjustments);

  return (
    <div className="columns">
      <section className="card grow" aria-labelledby="annotations-title">
        <h2 id="annotations-title">Annotations</h2>
        <ErrorAlert message={annotations.error && `Could not load the annotations: ${annotations.error}`} />
        <AnnotationList annotations={annotations.data ?? []} on_seek={on_seek} />
        {can_write && <AnnotationForm session_id={session_id} position_s={position_s} on_added={annotations.reload} />}
      </section>
      <section className="card grow" aria-labelledby="adjustments-title">
        <h2 id="adjustments-title">Score adjustments</h2>
        <ErrorAlert message={adjustments.error && `Could not load the adjustments: ${adjustments.error}`} />
        <AdjustmentList adjustments={adjustments.data ?? []} />
        {can_write && <AdjustmentForm session_id={session_id} on_added={adjustments.reload} />}
      </section>
    </div>
  );
}

function AnnotationList({ annotations, on_seek }: { annotations: Annotation[]; on_seek: (t: number) => void }) {
  if (annotations.length === 0) return <p className="muted">No annotations yet.</p>;
  return (
    <ul className="note-list" data-testid="annotations">
      {annotations.map((a) => (
        <li key={a.id}>
          <button type="button" className="link-button" onClick={() => on_seek(a.t_s)} aria-label={`Jump to ${format_seconds(a.t_s)}`}>
            {format_seconds(a.t_s)}
          </button>{' '}
          {a.text} <span className="muted">— {a.author}, {format_date_time(a.created_at)}</span>
        </li>
      ))}
    </ul>
  );
}

function AnnotationForm({ session_id, position_s, on_added }: { session_id: number; position_s: number; on_added: () => void }) {
  const [text, set_text] = useState('');
  const { busy, error, run } = useFormAction();

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    await run(async () => {
      await api.add_annotation(session_id, Math.max(0, position_s), text.trim());
      set_text('');
      on_added();
    }, 'Could not add the annotation');
  }

  return (
    <form onSubmit={on_submit} className="form" aria-label="Add annotation">
      <label htmlFor="annotation-text">Note at {format_seconds(position_s)}</label>
      <textarea id="annotation-text" required maxLength={2000} rows={2} value={text} onChange={(e) => set_text(e.target.value)} />
      <ErrorAlert message={error} />
      <button type="submit" className="button-primary" disabled={busy || !text.trim()}>
        Add annotation
      </button>
    </form>
  );
}

function AdjustmentList({ adjustments }: { adjustments: ScoreAdjustment[] }) {
  if (adjustments.length === 0) return <p className="muted">The computed result stands.</p>;
  // The latest one counts; the rest are history.
  return (
    <ol className="note-list" data-testid="adjustments" reversed>
      {[...adjustments].reverse().map((a, i) => (
        <li key={a.id} className={i > 0 ? 'muted' : undefined}>
          <span className={`badge ${a.passed ? 'badge-pass' : 'badge-fail'}`}>{a.passed ? 'Passed' : 'Not passed'}</span> {a.reason}{' '}
          <span className="muted">
            — {a.author}, {format_date_time(a.created_at)}
            {i === 0 ? ' (in force)' : ''}
          </span>
        </li>
      ))}
    </ol>
  );
}

function AdjustmentForm({ session_id, on_added }: { session_id: number; on_added: () => void }) {
  const [passed, set_passed] = useState(true);
  const [reason, set_reason] = useState('');
  const { busy, error, status, run } = useFormAction();

  async function on_submit(event: SubmitEvent<HTMLFormElement>) {
    event.preventDefault();
    await run(async () => {
      await api.adjust_score(session_id, passed, reason.trim());
      set_reason('');
      on_added();
      return `The attempt now counts as ${passed ? 'passed' : 'not passed'}.`;
    }, 'Could not adjust the score');
  }

  return (
    <form onSubmit={on_submit} className="form" aria-label="Adjust score">
      <label htmlFor="adjust-result">Result</label>
      <select id="adjust-result" value={passed ? 'pass' : 'fail'} onChange={(e) => set_passed(e.target.value === 'pass')}>
        <option value="pass">Passed</option>
        <option value="fail">Not passed</option>
      </select>
      <label htmlFor="adjust-reason">Reason</label>
      <textarea
        id="adjust-reason"
        required
        minLength={3}
        maxLength={500}
        rows={2}
        value={reason}
        onChange={(e) => set_reason(e.target.value)}
      />
      <p className="hint">3–500 characters; the trainee reads it, and the change is audited.</p>
      <ErrorAlert message={error} />
      <StatusMessage message={status} />
      <button type="submit" className="button-primary" disabled={busy}>
        Adjust score
      </button>
    </form>
  );
}
