import { act, screen, within } from '@testing-library/react';
import userEvent from '@testing-library/user-event';
import { afterEach, expect, it, vi } from 'vitest';
import type { CalibrationJob } from '../../api';
import { calibration_job, fake_server, render_with_queries } from '../../test_support';
import { CalibrationJobs, useCalibrationJobs } from './calibration_jobs';

afterEach(() => {
  vi.useRealTimers();
  vi.unstubAllGlobals();
});

const scenes = { scenes: [{ id: 'scenes/calibration/cube.json', title: 'Cube', model: 'mss', per: ['label'], has_example: false }] };

it('lists each job with its progress and offers Cancel while it has not ended', async () => {
  const running = calibration_job({ id: 8 });
  const done = calibration_job({ id: 7, status: 'done' });
  const sent = fake_server({
    'GET /api/calibration/scenes': scenes,
    'POST /api/calibration/jobs/8/cancel': { job: { ...running, status: 'cancelled' } },
  });
  const on_changed = vi.fn();
  const on_select = vi.fn();
  render_with_queries(<CalibrationJobs jobs={[running, done]} selected={null} on_select={on_select} on_changed={on_changed} />);

  expect(screen.getByTestId('calibration-job-8-progress').textContent).toBe(
    'iteration 12 · misfit 3.1e-4 · 480 of 2000 simulations',
  );
  expect(screen.getByTestId('calibration-job-8-status').textContent).toBe('Running');
  expect(screen.getByTestId('calibration-job-7-status').textContent).toBe('Done');
  // The scene by its file name, its title and who started the job in tooltips.
  expect((await screen.findAllByTitle('Cube')).map((s) => s.textContent)).toEqual(['cube.json', 'cube.json']);
  expect(screen.getAllByTitle('Started by admin')).toHaveLength(2);
  expect(screen.queryByRole('button', { name: 'Cancel calibration 7' })).toBeNull();

  const user = userEvent.setup();
  await user.click(screen.getByRole('button', { name: 'Show calibration 7' }));
  expect(on_select).toHaveBeenCalledWith(7);
  await user.click(screen.getByRole('button', { name: 'Cancel calibration 8' }));
  await vi.waitFor(() => expect(on_changed).toHaveBeenCalledOnce());
  expect(sent.at(-1)).toMatchObject({ method: 'POST', path: '/api/calibration/jobs/8/cancel' });
});

function JobStatuses() {
  const jobs = useCalibrationJobs();
  return (
    <ul>
      {jobs.data?.map((j) => (
        <li key={j.id}>{`${j.id} ${j.status}`}</li>
      ))}
    </ul>
  );
}

it('polls the list every second while a job runs, and stops once none does', async () => {
  vi.useFakeTimers({ toFake: ['setInterval', 'clearInterval'] });
  const answers: CalibrationJob[][] = [[calibration_job({})], [calibration_job({})], [calibration_job({ status: 'done' })]];
  let gets = 0;
  fake_server({
    'GET /api/calibration/jobs': () => ({ jobs: answers[Math.min(gets++, answers.length - 1)] }),
  });
  render_with_queries(<JobStatuses />);
  await screen.findByText('7 running');

  await act(() => vi.advanceTimersByTimeAsync(1000));
  expect(gets).toBe(2);
  await act(() => vi.advanceTimersByTimeAsync(1000));
  await within(screen.getByRole('list')).findByText('7 done');
  await act(() => vi.advanceTimersByTimeAsync(5000));
  expect(gets).toBe(3);
});
