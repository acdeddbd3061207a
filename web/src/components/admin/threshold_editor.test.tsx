import { screen, waitFor } from '@testing-library/react';
import userEvent from '@testing-library/user-event';
import { afterEach, expect, it, vi } from 'vitest';
import type { CurriculumEntry } from '../../api';
import { cut_area, fake_server, render_with_queries } from '../../test_support';
import { ThresholdEditor } from './threshold_editor';

afterEach(() => {
  vi.unstubAllGlobals();
});

const curriculum: CurriculumEntry = {
  id: 4,
  name: 'Cutting',
  definition: {
    name: 'Cutting',
    description: '',
    modules: [
      {
        key: 'basics',
        name: 'Basics',
        tasks: [
          {
            key: 'cut',
            name: 'Straight cut',
            instructions: '',
            metrics: [{ key: 'cut_area', threshold: { op: '>=', value: 6e-5 }, unit: 'm^2' }],
          },
        ],
      },
    ],
  },
};

it('shows a threshold in the display unit and sends it back in the stored unit', async () => {
  const sent = fake_server({
    'GET /api/metrics': [cut_area],
    'PUT /api/curricula/4': (definition: unknown) => ({ id: 4, name: 'Cutting', definition }),
  });
  const on_saved = vi.fn();
  render_with_queries(<ThresholdEditor curriculum={curriculum} on_saved={on_saved} />);

  const input = await screen.findByLabelText('Cut area at least');
  await waitFor(() => expect(input).toHaveProperty('value', '60'));
  expect(screen.getByText('mm²')).toBeDefined();

  const user = userEvent.setup();
  await user.clear(input);
  await user.type(input, '75');
  await user.click(screen.getByRole('button', { name: 'Save thresholds' }));

  await screen.findByText('Thresholds saved.');
  const put = sent.find((r) => r.method === 'PUT');
  expect(put?.path).toBe('/api/curricula/4');
  const body = put?.body as CurriculumEntry['definition'];
  expect(body.modules[0]?.tasks[0]?.metrics?.[0]?.threshold).toEqual({ op: '>=', value: 7.5e-5 });
  expect(on_saved).toHaveBeenCalledOnce();
  // The curriculum given stays as it was: the edit went into a copy.
  expect(curriculum.definition.modules[0]?.tasks[0]?.metrics?.[0]?.threshold.value).toBe(6e-5);
});
