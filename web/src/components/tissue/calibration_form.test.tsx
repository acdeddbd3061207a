import { screen, waitFor } from '@testing-library/react';
import userEvent from '@testing-library/user-event';
import { afterEach, expect, it, vi } from 'vitest';
import type { CalibrationScene } from '../../api';
import { calibration_job, fake_server, render_with_queries, Reply } from '../../test_support';
import { CalibrationForm } from './calibration_form';

afterEach(() => {
  vi.unstubAllGlobals();
});

const cube: CalibrationScene = {
  id: 'scenes/calibration/cube.json',
  title: 'Seed 004 cube (1 cm, mass-spring)',
  model: 'mss',
  per: ['label', 'node'],
  has_example: true,
};
const liver: CalibrationScene = {
  id: 'scenes/liver.json',
  title: 'Liver lobe',
  model: 'corotational',
  per: ['label'],
  has_example: false,
};

const csv = 'time_s,contact,x,y,z,dir_x,dir_y,dir_z,force_n\n0,0,0.005,0.005,0.01,0,0,-1,0\n';

it('posts the file’s text with the chosen scene, method, parameters and budget', async () => {
  const sent = fake_server({
    'GET /api/calibration/scenes': { scenes: [liver, cube] },
    'POST /api/calibration/jobs': new Reply(201, { job: calibration_job({ id: 12, status: 'queued', progress: null }) }),
  });
  const on_created = vi.fn();
  render_with_queries(<CalibrationForm on_created={on_created} shown_job={undefined} />);
  const user = userEvent.setup();

  const scene = await screen.findByLabelText('Scene');
  // Each scene by its file name and model, the title in a tooltip.
  expect(screen.getAllByRole('option', { name: /\.json/ }).map((o) => [o.textContent, o.title])).toEqual([
    ['liver.json (corotational)', 'Liver lobe'],
    ['cube.json (mss)', 'Seed 004 cube (1 cm, mass-spring)'],
  ]);
  // The first scene fits per label only.
  expect(screen.getAllByRole('option', { name: /^Per / }).map((o) => o.textContent)).toEqual(['Per label']);
  expect(screen.getByLabelText('Method')).toHaveProperty('value', 'lm');
  expect(screen.queryByRole('link', { name: 'Example data' })).toBeNull();

  await user.selectOptions(scene, cube.id);
  expect(screen.getByRole('link', { name: 'Example data' }).getAttribute('href')).toBe(
    '/api/calibration/example?scene=scenes%2Fcalibration%2Fcube.json',
  );
  await user.selectOptions(screen.getByLabelText('Method'), 'cmaes');
  await user.selectOptions(screen.getByLabelText('Parameters'), 'node');
  const budget = screen.getByLabelText('Budget (simulations)');
  expect(budget).toHaveProperty('value', '2000');
  await user.clear(budget);
  await user.type(budget, '500');
  await user.upload(screen.getByLabelText('Data file (CSV)'), new File([csv], 'pushes.csv', { type: 'text/csv' }));
  expect(screen.getByTestId('calibration-data-name').textContent).toBe('pushes.csv');

  await user.click(screen.getByRole('button', { name: 'Run calibration' }));

  await screen.findByText('Calibration 12 queued.');
  const post = sent.find((r) => r.method === 'POST');
  expect(post?.path).toBe('/api/calibration/jobs');
  expect(post?.body).toEqual({
    scene: cube.id,
    method: 'cmaes',
    per: 'node',
    budget: 500,
    data: csv,
    data_name: 'pushes.csv',
  });
  expect(on_created).toHaveBeenCalledWith(expect.objectContaining({ id: 12 }));
});

it('shows the server’s reason for refusing a data file, and creates nothing', async () => {
  const refusal = "data: line 7: force_n 'abc' is not a number";
  fake_server({
    'GET /api/calibration/scenes': { scenes: [cube] },
    'POST /api/calibration/jobs': new Reply(400, { error: refusal }),
  });
  const on_created = vi.fn();
  render_with_queries(<CalibrationForm on_created={on_created} shown_job={undefined} />);
  const user = userEvent.setup();

  await user.upload(await screen.findByLabelText('Data file (CSV)'), new File(['bad'], 'bad.csv', { type: 'text/csv' }));
  await user.click(screen.getByRole('button', { name: 'Run calibration' }));

  const alert = await screen.findByRole('alert');
  expect(alert.textContent).toContain(refusal);
  expect(on_created).not.toHaveBeenCalled();
  // The file stays chosen, to be fixed and sent again.
  await waitFor(() => expect(screen.getByRole('button', { name: 'Run calibration' })).toHaveProperty('disabled', false));
  expect(screen.getByTestId('calibration-data-name').textContent).toBe('bad.csv');
});

/** The form with job 12 queued through it (its "queued" message showing); for the message's life. */
async function queue_job_12() {
  fake_server({
    'GET /api/calibration/scenes': { scenes: [cube] },
    'POST /api/calibration/jobs': new Reply(201, { job: calibration_job({ id: 12, status: 'queued', progress: null }) }),
  });
  const { rerender } = render_with_queries(<CalibrationForm on_created={vi.fn()} shown_job={undefined} />);
  const user = userEvent.setup();
  await user.upload(await screen.findByLabelText('Data file (CSV)'), new File([csv], 'pushes.csv', { type: 'text/csv' }));
  await user.click(screen.getByRole('button', { name: 'Run calibration' }));
  await screen.findByText('Calibration 12 queued.');
  return { rerender };
}

it('drops “Calibration N queued.” once that job has ended', async () => {
  const { rerender } = await queue_job_12();

  // Listed and running: the message holds.
  rerender(<CalibrationForm on_created={vi.fn()} shown_job={calibration_job({ id: 12 })} />);
  expect(screen.getByRole('status').textContent).toBe('Calibration 12 queued.');
  rerender(<CalibrationForm on_created={vi.fn()} shown_job={calibration_job({ id: 12, status: 'done' })} />);
  expect(screen.queryByRole('status')).toBeNull();
});

it('drops “Calibration N queued.” when another job is shown, for good', async () => {
  const { rerender } = await queue_job_12();

  rerender(<CalibrationForm on_created={vi.fn()} shown_job={calibration_job({ id: 9, status: 'done' })} />);
  expect(screen.queryByRole('status')).toBeNull();
  rerender(<CalibrationForm on_created={vi.fn()} shown_job={calibration_job({ id: 12 })} />);
  expect(screen.queryByRole('status')).toBeNull();
});
