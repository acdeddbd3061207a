// Helpers for component tests: a fake server answering fetch from a table of JSON bodies, and a
// render inside a fresh request cache (so that no answer leaks from one test into the next).
import { QueryClientProvider } from '@tanstack/react-query';
import { render, type RenderResult } from '@testing-library/react';
import type { ReactElement } from 'react';
import { vi } from 'vitest';
import type { CalibrationJob, MetricInfo } from './api';
import { make_query_client } from './query_client';
import type { StreamMetrics } from './stream';

export interface SentRequest {
  method: string;
  path: string;
  body: unknown;
}

/** A route's answer with another status than 200, e.g. `new Reply(409, { error: '…' })`. */
export class Reply {
  constructor(
    readonly status: number,
    readonly body: unknown,
  ) {}
}

/**
 * Replaces fetch: "GET /api/x" answers `routes["GET /api/x"]` with 200 (a function of the request
 * body for other methods; a Reply for another status), anything else 404. Returns the requests
 * sent, in order.
 */
export function fake_server(routes: Record<string, unknown>): SentRequest[] {
  const sent: SentRequest[] = [];
  const fetch = vi.fn((input: RequestInfo | URL, init?: RequestInit) => {
    const method = init?.method ?? 'GET';
    const path = typeof input === 'string' ? input : input instanceof URL ? input.pathname : input.url;
    const body: unknown = typeof init?.body === 'string' ? JSON.parse(init.body) : undefined;
    sent.push({ method, path, body });
    const key = `${method} ${path}`;
    if (!(key in routes)) {
      return Promise.resolve(new Response(JSON.stringify({ error: `no ${key}` }), { status: 404 }));
    }
    const route = routes[key];
    const answer: unknown = typeof route === 'function' ? (route as (b: unknown) => unknown)(body) : route;
    if (answer instanceof Reply) return Promise.resolve(new Response(JSON.stringify(answer.body), { status: answer.status }));
    return Promise.resolve(new Response(JSON.stringify(answer), { status: 200 }));
  });
  vi.stubGlobal('fetch', fetch);
  return sent;
}

/** Renders `ui` in a fresh request cache, which a `rerender` of the result keeps. */
export function render_with_queries(ui: ReactElement): RenderResult {
  const client = make_query_client();
  return render(ui, { wrapper: ({ children }) => <QueryClientProvider client={client}>{children}</QueryClientProvider> });
}

/** A catalogue entry like the server's cut area: stored in m², shown in mm² with no decimals. */
export const cut_area: MetricInfo = {
  key: 'cut_area',
  name: 'Cut area',
  unit: 'm^2',
  display_unit: 'mm²',
  display_scale: 1e6,
  decimals: 0,
  better: 'higher',
  definition: 'The area of tissue cut.',
};

/** A catalogue entry for a force in N, shown with two decimals. */
export const peak_force: MetricInfo = {
  key: 'peak_force',
  name: 'Peak force',
  unit: 'N',
  display_unit: 'N',
  display_scale: 1,
  decimals: 2,
  better: 'lower',
  definition: 'The largest force on the tissue.',
};

/** View-stream metrics as the server sends them, with `change` over a quiet running session's. */
export function stream_metrics(change: Partial<StreamMetrics>): StreamMetrics {
  return {
    state: 'running',
    reason: '',
    sim_time_s: 0,
    agent_online: true,
    tool: [0, 0, 0],
    force_n: 0,
    peak_force_n: 0,
    path_length_m: 0,
    contact: false,
    steps: 0,
    sim_rate_hz: 500,
    frames_sent: 1,
    ...change,
  };
}

/** A calibration job as GET /api/calibration/jobs lists it, with `change` over a running one's. */
export function calibration_job(change: Partial<CalibrationJob>): CalibrationJob {
  return {
    id: 7,
    scene: 'scenes/calibration/cube.json',
    method: 'lm',
    per: 'label',
    budget: 2000,
    data_name: 'pushes.csv',
    contacts: 2,
    samples: 200,
    status: 'running',
    progress: { iteration: 12, evaluations: 480, misfit: 3.1e-4 },
    created_at: '2026-11-29T15:00:00Z',
    created_by: 'admin',
    finished_at: null,
    error: null,
    material: null,
    ...change,
  };
}
