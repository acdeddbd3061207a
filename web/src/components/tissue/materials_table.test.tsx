import { screen, within } from '@testing-library/react';
import { afterEach, expect, it, vi } from 'vitest';
import type { Material } from '../../api';
import { fake_server, render_with_queries } from '../../test_support';
import { MaterialsTable } from './materials_table';

afterEach(() => {
  vi.unstubAllGlobals();
});

const cube: Material = {
  id: 3,
  name: 'Calibrated cube',
  scene: 'scenes/calibration/cube.json',
  model: 'mss',
  E: 3600,
  nu: 0.3,
  density: 1040,
  damping: 0.1,
  method: 'lm',
  misfit: 1.4e-29,
  job: 1,
  created_at: '2026-11-29T16:10:00Z',
  created_by: 'Ada Admin',
  tasks: ['palpation'],
};
const liver: Material = { ...cube, id: 4, name: 'Liver', scene: 'scenes/liver.json', model: 'corotational', nu: 0.45, tasks: [] };

it('shows a mass-spring material without a Poisson’s ratio, and the scene by its file name', async () => {
  fake_server({
    'GET /api/calibration/scenes': {
      scenes: [{ id: cube.scene, title: 'Seed 004 cube', model: 'mss', per: ['label'], has_example: true }],
    },
  });
  render_with_queries(<MaterialsTable materials={[cube, liver]} />);

  const table = within(screen.getByTestId('materials'));
  expect(table.getByTitle("Poisson's ratio").textContent).toBe('ν');
  const rows = table.getAllByRole('row').slice(1);
  const cells = rows.map((r) => within(r).getAllByRole('cell').map((c) => c.textContent));
  expect(cells.map((c) => c.slice(0, 5))).toEqual([
    ['Calibrated cube', 'cube.json', 'mss', '3.60 kPa', '—'],
    ['Liver', 'liver.json', 'corotational', '3.60 kPa', '0.45'],
  ]);
  expect((await table.findByTitle('Seed 004 cube')).textContent).toBe('cube.json');
  expect(table.getByTestId('material-3-tasks').textContent).toBe('palpation');
});
