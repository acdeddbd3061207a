import { screen, within } from '@testing-library/react';
import { afterEach, describe, expect, it, vi } from 'vitest';
import type { Progress, Score, ScoreAdjustment, Session } from '../../api';
import { fake_server, peak_force, render_with_queries } from '../../test_support';
import { SessionResult } from './session_result';

afterEach(() => {
  vi.unstubAllGlobals();
});

const session: Session = {
  id: 7,
  trainee_id: 3,
  trainee: 'trainee',
  station_id: 1,
  station: 'Bench 1',
  task: 'palpation',
  state: 'finished',
  started_at: '2026-03-02T10:00:00Z',
  ended_at: '2026-03-02T10:05:00Z',
};

function score(id: number, metric: string, value: number, passed: boolean, criterion: boolean, session_id = 7): Score {
  return {
    id,
    session_id,
    trainee: 'trainee',
    task: 'palpation',
    metric,
    value,
    unit: metric === 'peak_force' ? 'N' : 'count',
    passed,
    created_at: '2026-03-02T10:05:00Z',
    criterion,
    threshold: metric === 'peak_force' ? { op: '<=', value: 2 } : { op: '>=', value: 1 },
  };
}

function task(key: string, name: string, consecutive_passes: number, mastered: boolean) {
  return {
    key,
    name,
    module: 'basics',
    prerequisites: [],
    attempts: 4,
    passed_attempts: 2,
    consecutive_passes,
    required_passes: 3,
    mastered,
    unlocked: true,
    missing_prerequisites: [],
    locked_reason: '',
  };
}

/** The server's answers; `passed` is its verdict on session 7. */
function server(scores: Score[], progress: Progress, adjustments: ScoreAdjustment[] = [], passed: boolean | null = false) {
  fake_server({
    'GET /api/sessions/7': { ...session, live: null, passed },
    'GET /api/scores': scores,
    'GET /api/recordings': [],
    'GET /api/sessions/7/adjustments': adjustments,
    'GET /api/trainees/3/progress': progress,
    'GET /api/benchmarks': [],
    'GET /api/metrics': [peak_force],
  });
}

describe('SessionResult', () => {
  it('says which metric missed its threshold and where the trainee stands', async () => {
    server(
      [
        score(1, 'targets_touched', 5, true, true),
        score(2, 'peak_force', 2.5, false, false),
        score(3, 'peak_force', 9, false, false, 8), // another session's: not shown
      ],
      { trainee_id: 3, curriculum: 'Basics', next_task: 'palpation', tasks: [task('palpation', 'Palpation', 1, false)] },
    );
    render_with_queries(<SessionResult session={session} />);

    const verdict = await screen.findByTestId('attempt-verdict');
    expect(verdict.textContent).toBe('Not passed: peak force missed its threshold.');
    expect((await screen.findByTestId('attempt-standing')).textContent).toBe('Palpation: 1 of 3 passes in a row.');

    const criteria = within(screen.getByRole('region', { name: 'Completion criteria' }));
    const item = criteria.getByRole('listitem');
    expect(item.textContent).toContain('Met');
    expect(item.textContent).toContain('targets_touched: 5');
    expect(item.textContent).toContain('(needed at least 1)');
  });

  it('names the undone criterion and, once a task is mastered, the next one', async () => {
    server(
      [score(1, 'targets_touched', 0, false, true), score(2, 'peak_force', 1.5, true, false)],
      {
        trainee_id: 3,
        curriculum: 'Basics',
        next_task: 'bimanual',
        tasks: [task('palpation', 'Palpation', 3, true), task('bimanual', 'Two-handed palpation', 0, false)],
      },
    );
    render_with_queries(<SessionResult session={session} />);

    expect((await screen.findByTestId('attempt-verdict')).textContent).toBe(
      'Not passed: the task was not done (targets_touched), whatever the other metrics.',
    );
    expect((await screen.findByTestId('attempt-standing')).textContent).toBe(
      'Palpation: mastered; next: Two-handed palpation.',
    );
    expect(screen.getByText('Not met')).toBeDefined();
  });

  it('follows an instructor’s adjustment over the scores', async () => {
    const adjustment: ScoreAdjustment = {
      id: 1,
      session_id: 7,
      author: 'instructor',
      passed: true,
      reason: 'sensor glitch',
      created_at: '2026-03-02T11:00:00Z',
    };
    server(
      [score(2, 'peak_force', 2.5, false, false)],
      { trainee_id: 3, curriculum: 'Basics', next_task: null, tasks: [task('palpation', 'Palpation', 3, true)] },
      [adjustment],
      true,
    );
    render_with_queries(<SessionResult session={session} />);

    const verdict = await screen.findByTestId('attempt-verdict');
    await vi.waitFor(() => expect(verdict.textContent).toBe('Passed, as adjusted by instructor: sensor glitch'));
    expect((await screen.findByTestId('attempt-standing')).textContent).toBe(
      'Palpation: mastered; every task of the curriculum is mastered.',
    );
  });

  it('says the result is being worked out until the server has decided', async () => {
    server(
      [score(2, 'peak_force', 2.5, true, false)],
      { trainee_id: 3, curriculum: 'Basics', next_task: 'palpation', tasks: [task('palpation', 'Palpation', 0, false)] },
      [],
      null,
    );
    render_with_queries(<SessionResult session={session} />);
    expect((await screen.findByText('Working out the result…')).getAttribute('role')).toBe('status');
    expect(screen.queryByTestId('attempt-verdict')).toBeNull();
  });
});
