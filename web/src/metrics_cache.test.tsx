import { screen } from '@testing-library/react';
import { afterEach, expect, it, vi } from 'vitest';
import { useMetricCatalogue } from './metrics';
import { fake_server, peak_force, render_with_queries } from './test_support';

afterEach(() => {
  vi.unstubAllGlobals();
});

function Name({ label }: { label: string }) {
  const catalogue = useMetricCatalogue();
  return <p>{`${label}: ${catalogue?.get('peak_force')?.name ?? 'loading'}`}</p>;
}

it('fetches the metric catalogue once for every component that needs it', async () => {
  const sent = fake_server({ 'GET /api/metrics': [peak_force] });
  render_with_queries(
    <>
      <Name label="first" />
      <Name label="second" />
      <Name label="third" />
    </>,
  );
  await screen.findByText('first: Peak force');
  await screen.findByText('third: Peak force');
  expect(sent.filter((r) => r.path === '/api/metrics')).toHaveLength(1);
});
