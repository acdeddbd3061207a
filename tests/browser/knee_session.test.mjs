// Browser test of the knee at the demo's Arthroscopy station (node --test): its real agent holds a
// simulated arthroscope at the anterolateral portal and a probe at the anteromedial one, both
// through their portals' kinematics, touring the joint's landmarks (deploy/agent/knee_*_tour.json).
// A trainee walks up and runs the diagnostic tour: the picture is the arthroscope's and changes as
// the scope turns, the probe's landmark visits are scored; an instructor replays it. Needs
// web/dist, the server and agent binaries; see support.mjs.
import assert from 'node:assert/strict';
import path from 'node:path';
import {
  api_call,
  browser_suite,
  canvas_state,
  click_for_response,
  demo,
  log_in,
  region,
  repo,
  sees,
  snap,
  wait_for_canvas,
  walk_up_and_start,
} from './support.mjs';

const { scenario } = browser_suite({
  time_zone: 'Europe/Berlin',
  with_agent: true,
  agent: {
    token: demo.arthroscopy_station_token,
    args: [
      '--device', `knee-scope:${path.join(repo, 'deploy/agent/knee_scope_tour.json')}`,
      '--device', `knee-instrument:${path.join(repo, 'deploy/agent/knee_probe_tour.json')}`,
    ],
  },
});

// The probe rests on the last landmark (the lateral meniscus's anterior horn) from 22 s to 24 s
// of the agent's clock, which started a moment before the session's.
const tour_end_s = 23;

scenario(
  'a trainee tours the knee through the arthroscope at the arthroscopy station, and an instructor replays it',
  async (page) => {
    // The resident has mastered the palpation tasks that unlock this one (the server refuses locked
    // tasks).
    assert.equal((await log_in(page, demo.resident)).status(), 200);
    await page.waitForURL('**/trainee');
    const session = await walk_up_and_start(page, 'Arthroscopy station', 'knee_tour', 'Inspect the knee through the 30-degree arthroscope');

    // Live: the arthroscope's picture of the joint, turning with the scope from the notch to the
    // medial meniscus (2 s), then to the medial plateau (10 s).
    await wait_for_canvas(page, 'live-canvas', { time_min: 1 }, 'a first live frame');
    const first = await canvas_state(page, 'live-canvas');
    assert.ok(Math.max(...first.grid) - Math.min(...first.grid) > 20, 'the first frame is a picture of the joint');
    await wait_for_canvas(page, 'live-canvas', { time_min: 11 }, '11 simulated seconds', 40_000);
    const turned = await canvas_state(page, 'live-canvas');
    const changed = first.grid.filter((v, i) => Math.abs(v - turned.grid[i]) > 8).length;
    assert.ok(changed >= first.grid.length / 10, `the picture changed with the scope in ${changed} of ${first.grid.length} samples`);
    await snap(page, 'trainee-knee-live');
    await wait_for_canvas(page, 'live-canvas', { time_min: tour_end_s }, 'the end of the tour', 40_000);

    page.once('dialog', (dialog) => dialog.accept());
    const stopped = await click_for_response(page, page.getByRole('button', { name: 'Stop' }), 'POST', new RegExp(`^/api/sessions/${session.id}/stop$`));
    assert.equal(stopped.status(), 200, await stopped.text());
    const result = region(page, 'Result');
    // Every landmark reached is a completion criterion of the tour, listed apart from the metrics.
    const criteria = result.getByRole('region', { name: 'Completion criteria' });
    await sees(criteria.getByRole('listitem').filter({ hasText: /^Met Share of targets reached: 100 %/ }), 'the landmark visits in the result');
    const scores = (await api_call(page, 'GET', '/api/scores')).body;
    const visited = scores.find((s) => s.session_id === session.id && s.metric === 'targets_fraction');
    assert.ok(visited, JSON.stringify(scores).slice(0, 2000));
    assert.equal(Number(visited.value), 1, `every landmark was touched: ${JSON.stringify(visited)}`);
    await snap(page, 'trainee-knee-result');

    // --- The instructor replays it. ---
    await click_for_response(page, page.getByRole('button', { name: 'Log out' }), 'POST', /^\/api\/logout$/);
    await page.waitForURL('**/login');
    assert.equal((await log_in(page, demo.instructor)).status(), 200);
    await page.waitForURL('**/instructor');
    await page.goto(`/recordings/${session.live.recording_id}`);
    // It opens paused on its first picture; Play runs it.
    await wait_for_canvas(page, 'replay-canvas', {}, 'the first replay frame');
    const play = page.getByTestId('replay-play');
    await sees(play.filter({ hasText: 'Play' }), 'a replay that opens paused');
    await play.click();
    await wait_for_canvas(page, 'replay-canvas', { time_min: 3 }, 'the replay under way', 30_000);
    const replayed = await canvas_state(page, 'replay-canvas');
    assert.ok(Math.max(...replayed.grid) - Math.min(...replayed.grid) > 20, 'the replay shows the joint');
    await snap(page, 'instructor-knee-replay');
  },
  { timeout_ms: 170_000 },
);
