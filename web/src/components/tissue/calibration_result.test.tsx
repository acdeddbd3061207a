import { screen, within } from '@testing-library/react';
import userEvent from '@testing-library/user-event';
import { afterEach, describe, expect, it, vi } from 'vitest';
import type { CalibratedValue, CalibrationResult as Result } from '../../api';
import { calibration_job, fake_server, render_with_queries, Reply } from '../../test_support';
import { CalibrationResult } from './calibration_result';

// uPlot draws on a canvas, which jsdom has not: the charts themselves are not under test here.
vi.mock('../../use_uplot', () => ({ useUplot: () => ({ current: null }) }));

afterEach(() => {
  vi.unstubAllGlobals();
});

const done = calibration_job({ id: 7, status: 'done', finished_at: '2026-11-29T15:02:00Z' });

function result(values: CalibratedValue[], change: Partial<Result> = {}): Result {
  return {
    material: { model: 'mss', E: 12345, nu: 0.45, density: 1000, damping: 0.1 },
    calibration: {
      method: 'lm',
      parameters: 'label',
      misfit: 4.1e-4,
      start_misfit: 0.32,
      evaluations: 180,
      iterations: 9,
      seconds: 2.5,
      stopped: 'converged',
      history: [0.1, 0.01, 4.1e-4],
      values,
      fits: [
        {
          contact: 0,
          node: 12,
          distance: 0.0004,
          time: [0.001, 0.002],
          force: [0.001, 0.002],
          measured: [-0.001, -0.002],
          start: [-0.0015, -0.003],
          fitted: [-0.001, -0.00201],
        },
      ],
    },
    ...change,
  };
}

const label_values: CalibratedValue[] = [
  { name: 'E[0]', owner: 0, start: 10000, value: 12345, spread: 500 },
  { name: 'nu[0]', owner: 0, start: 0.4, value: 0.45, spread: 0.012 },
];

describe('CalibrationResult of a done job', () => {
  it('shows the constants in kPa with their spreads, and the misfit before and after', async () => {
    fake_server({ 'GET /api/calibration/jobs/7': { job: done, result: result(label_values) } });
    render_with_queries(<CalibrationResult job={done} on_saved={vi.fn()} />);

    const table = within(await screen.findByTestId('calibration-values'));
    const rows = table.getAllByRole('row').slice(1);
    expect(rows.map((r) => within(r).getAllByRole('cell').map((c) => c.textContent))).toEqual([
      ['E, label 0', '10.0 kPa', '12.3 kPa', '± 4.1 %'],
      ['ν, label 0', '0.4', '0.45', '± 2.7 %'],
    ]);
    expect(table.getByText('ν, label 0').title).toBe('nu[0]');
    expect(screen.getByTestId('calibration-misfit').textContent).toBe('0.32 → 4.1e-4');
    expect(screen.getByTestId('calibration-stopped').textContent).toBe('converged');
    expect(screen.getByTestId('calibration-fit-summary').textContent).toContain('measured -2.00 mm');
  });

  it('shows the first 20 node moduli and a summary of all', async () => {
    const moduli = Array.from({ length: 30 }, (_, i) => 1000 * (i + 1));
    const values = moduli.map((v, i) => ({ name: `E[${i}]`, owner: i, start: 10000, value: v, spread: 100 }));
    const per_node = result(values, { node_moduli: moduli });
    per_node.calibration.parameters = 'node';
    fake_server({ 'GET /api/calibration/jobs/7': { job: done, result: per_node } });
    render_with_queries(<CalibrationResult job={{ ...done, per: 'node' }} on_saved={vi.fn()} />);

    const table = await screen.findByTestId('calibration-values');
    expect(within(table).getAllByRole('row')).toHaveLength(1 + 20);
    expect(within(table).getByTitle('E[17]').textContent).toBe('E, node 17');
    // The search's objective, not the data's misfit, per node.
    expect(screen.getByTestId('calibration-history').textContent).toContain('Objective per iteration');
    expect(screen.getByTestId('node-moduli-summary').textContent).toBe(
      'The first 20 of 30 values. Node moduli (30 nodes): min 1.00 kPa, median 15.5 kPa, max 30.0 kPa.',
    );
  });
});

describe('Save material', () => {
  it('posts the job and the name, and says so in place of the form', async () => {
    const sent = fake_server({
      'GET /api/calibration/jobs/7': { job: done, result: result(label_values) },
      'POST /api/materials': new Reply(201, { material: { id: 3, name: 'Liver (probe 2)' } }),
    });
    const on_saved = vi.fn();
    render_with_queries(<CalibrationResult job={done} on_saved={on_saved} />);
    const user = userEvent.setup();

    const form = within(await screen.findByRole('form', { name: 'Save material' }));
    await user.type(form.getByLabelText('Material name'), 'Liver (probe 2)');
    await user.click(form.getByRole('button', { name: 'Save material' }));

    expect((await screen.findByTestId('calibration-saved-as')).textContent).toBe('Saved as material “Liver (probe 2)”.');
    expect(screen.queryByRole('form', { name: 'Save material' })).toBeNull();
    expect(screen.getAllByText(/Saved/)).toHaveLength(1);
    expect(sent.find((r) => r.method === 'POST')).toEqual({
      method: 'POST',
      path: '/api/materials',
      body: { job: 7, name: 'Liver (probe 2)' },
    });
    expect(on_saved).toHaveBeenCalledOnce();
  });

  it('offers no form for a job already saved', async () => {
    const saved = { ...done, material: 'Liver' };
    fake_server({ 'GET /api/calibration/jobs/7': { job: saved, result: result(label_values) } });
    render_with_queries(<CalibrationResult job={saved} on_saved={vi.fn()} />);

    expect((await screen.findByTestId('calibration-saved-as')).textContent).toBe('Saved as material “Liver”.');
    expect(screen.queryByRole('form', { name: 'Save material' })).toBeNull();
  });

  it('shows why the server refuses a name in use', async () => {
    fake_server({
      'GET /api/calibration/jobs/7': { job: done, result: result(label_values) },
      'POST /api/materials': new Reply(409, { error: 'a material named "Liver" exists' }),
    });
    const on_saved = vi.fn();
    render_with_queries(<CalibrationResult job={done} on_saved={on_saved} />);
    const user = userEvent.setup();

    const form = within(await screen.findByRole('form', { name: 'Save material' }));
    await user.type(form.getByLabelText('Material name'), 'Liver');
    await user.click(form.getByRole('button', { name: 'Save material' }));

    expect((await form.findByRole('alert')).textContent).toContain('a material named "Liver" exists');
    expect(on_saved).not.toHaveBeenCalled();
  });
});

it('shows a running job’s progress and loads no result', () => {
  const sent = fake_server({});
  render_with_queries(<CalibrationResult job={calibration_job({})} on_saved={vi.fn()} />);
  expect(screen.getByRole('status').textContent).toBe('iteration 12 · misfit 3.1e-4 · 480 of 2000 simulations');
  expect(sent).toEqual([]);
});

it('shows what a cancelled job found, without offering to save it', async () => {
  const cancelled = { ...done, status: 'cancelled' as const, error: 'cancelled' };
  fake_server({ 'GET /api/calibration/jobs/7': { job: cancelled, result: result(label_values) } });
  render_with_queries(<CalibrationResult job={cancelled} on_saved={vi.fn()} />);

  await screen.findByTestId('calibration-values');
  expect(screen.queryByRole('form', { name: 'Save material' })).toBeNull();
});
