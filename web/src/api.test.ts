import { afterEach, describe, expect, it, vi } from 'vitest';
import { api, ApiError, parse_answer, schemas } from './api';
import { fake_server } from './test_support';

afterEach(() => {
  vi.unstubAllGlobals();
});

const station = { id: 1, name: 'Bench 1', location: 'Lab', kind: 'bench', retired: false, online: true };

describe('parse_answer', () => {
  it('keeps the fields the dashboard reads and drops unknown ones', () => {
    const parsed = parse_answer('GET /api/stations', schemas.stations, [{ ...station, retired: false }]);
    expect(parsed).toEqual([station]);
  });

  it('names the endpoint and the first field that does not fit', () => {
    const answer = [station, { ...station, id: 2, online: 'yes' }];
    expect(() => parse_answer('GET /api/stations', schemas.stations, answer)).toThrow(ApiError);
    expect(() => parse_answer('GET /api/stations', schemas.stations, answer)).toThrow(
      /^Unexpected answer from GET \/api\/stations: \[1\]\.online: .*expected boolean/,
    );
  });

  it('names a missing nested field by its path', () => {
    const score = {
      id: 1,
      session_id: 2,
      trainee: 'trainee',
      task: 'palpation',
      metric: 'peak_force',
      value: 1,
      unit: 'N',
      passed: true,
      created_at: '2026-01-01T00:00:00Z',
      criterion: false,
      threshold: { op: '<=' },
    };
    expect(() => parse_answer('GET /api/scores', schemas.scores, [score])).toThrow(/: \[0\]\.threshold\.value: /);
  });

  it('keeps the fields of a curriculum definition it does not know, which go back to the server', () => {
    const entry = {
      id: 1,
      name: 'Basics',
      definition: {
        name: 'Basics',
        description: '',
        version: 3,
        modules: [{ key: 'm', name: 'M', tasks: [{ key: 't', name: 'T', instructions: '', required_passes: 3 }] }],
      },
    };
    const [parsed] = parse_answer('GET /api/curricula', schemas.curricula, [entry]);
    expect(parsed?.definition).toEqual(entry.definition);
  });
});

describe('api', () => {
  it('rejects a GET answer the schema refuses with the endpoint in the message', async () => {
    fake_server({ 'GET /api/me': { id: 1, username: 'admin', display_name: 'Admin', role: 'superuser' } });
    await expect(api.me()).rejects.toThrow(/Unexpected answer from GET \/api\/me: role: /);
  });

  it('passes the server’s own error message on', async () => {
    fake_server({});
    await expect(api.stations()).rejects.toThrow('no GET /api/stations');
  });
});
