// Browser test of a surgical scene at a station (node --test): the demo's Surgical station, whose
// real agent plays a scalpel stroke along the liver's marked line (deploy/agent/liver_cut_demo.json).
// A trainee walks up, runs the liver task and sees the cut in the live metrics and the result; an
// instructor opens the review and jumps to the simulation's cut marker. Needs web/dist, the server
// and agent binaries; see support.mjs.
import assert from 'node:assert/strict';
import path from 'node:path';
import {
  api_call,
  browser_suite,
  canvas_state,
  click_for_response,
  demo,
  log_in,
  metric,
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
    token: demo.surgical_station_token,
    args: ['--script', path.join(repo, 'deploy/agent/liver_cut_demo.json')],
  },
});

// The agent's script draws the blade along the line from 3 s to 9 s and lifts it out by 10 s
// (its clock started a moment before the session's).
const stroke_end_s = 10.5;

scenario(
  'a trainee cuts the liver along the marked line at the surgical station, and an instructor jumps to the cut',
  async (page) => {
    // The resident has mastered the palpation tasks that unlock this one (the server refuses locked
    // tasks).
    assert.equal((await log_in(page, demo.resident)).status(), 200);
    await page.waitForURL('**/trainee');
    // Walk up to the Surgical station (the only one online), then start the liver task there.
    // Only the liver task is offered there: the palpation tasks need a bench station.
    const session = await walk_up_and_start(page, 'Surgical station', 'liver_cut', 'Cut the liver along the line', ['liver_cut']);

    // Live: the picture, the two hands, and the cut growing as the blade moves along the line.
    await wait_for_canvas(page, 'live-canvas', {}, 'a first live frame');
    const first = await canvas_state(page, 'live-canvas');
    assert.ok(Math.max(...first.grid) - Math.min(...first.grid) > 20, 'the first frame is a picture of the liver');
    await sees(metric(page, 'never_event').filter({ hasText: 'No' }), 'no protected structure cut');
    await wait_for_canvas(page, 'live-canvas', { time_min: 6 }, '6 simulated seconds', 30_000);
    await sees(metric(page, 'cut').filter({ hasText: /^[1-9][0-9.]* mm²/ }), 'the cut growing during the stroke');
    await snap(page, 'trainee-liver-live');
    await wait_for_canvas(page, 'live-canvas', { time_min: stroke_end_s }, 'the end of the stroke', 30_000);
    const cut_mm2 = Number((await metric(page, 'cut').textContent()).split(' ')[0]);
    assert.ok(cut_mm2 > 60, `the stroke cut ${cut_mm2} mm²`);
    const after_stroke = await canvas_state(page, 'live-canvas');
    const changed = first.grid.filter((v, i) => Math.abs(v - after_stroke.grid[i]) > 8).length;
    assert.ok(changed >= 5, `the picture changed in ${changed} sampled pixels`);
    await snap(page, 'trainee-liver-cut');
    // The trainee trains with the laparoscope's picture: no switch to the outside view.
    assert.equal(await page.getByRole('group', { name: 'Camera' }).count(), 0, 'no camera switch for a trainee');

    page.once('dialog', (dialog) => dialog.accept());
    const stopped = await click_for_response(page, page.getByRole('button', { name: 'Stop' }), 'POST', new RegExp(`^/api/sessions/${session.id}/stop$`));
    assert.equal(stopped.status(), 200, await stopped.text());
    const result = region(page, 'Result');
    await sees(result.getByTestId('attempt-verdict').filter({ hasText: /^Passed/ }), 'a passed attempt');
    for (const key of ['cut_area_m2', 'cut_on_target_fraction', 'never_events']) {
      await sees(result.getByRole('row').filter({ hasText: key }), `the score "${key}" in the result`);
    }
    const criteria = result.getByRole('region', { name: 'Completion criteria' });
    await sees(criteria.getByRole('listitem').filter({ hasText: /^Met Cut on the line/ }), 'the cut criterion met');
    await sees(criteria.getByRole('listitem').filter({ hasText: /^Met Tools on the tissue/ }), 'the contact criterion met');
    await snap(page, 'trainee-liver-result');
    // Bookings follow sessions: the end of the session completed the walk-up booking, so the rest
    // of the slot is free.
    const bookings = (await api_call(page, 'GET', '/api/bookings')).body;
    const surgical = bookings.filter((b) => b.station_name === 'Surgical station');
    assert.equal(surgical[0]?.status, 'completed', JSON.stringify(surgical));

    // --- The instructor reviews it: the simulation's cut is a marker that jumps the replay. ---
    await click_for_response(page, page.getByRole('button', { name: 'Log out' }), 'POST', /^\/api\/logout$/);
    await page.waitForURL('**/login');
    assert.equal((await log_in(page, demo.instructor)).status(), 200);
    await page.waitForURL('**/instructor');
    await page.goto(`/recordings/${session.live.recording_id}`);
    await wait_for_canvas(page, 'replay-canvas', {}, 'a first replay frame');
    const cut = region(page, 'Events').locator('[data-testid="event-marker"][data-kind="cut"][data-source="simulation"]');
    await sees(cut, 'the cut marker');
    const review = (await api_call(page, 'GET', `/api/sessions/${session.id}/review`)).body;
    const event = review.events.find((e) => e.kind === 'cut' && e.source === 'simulation');
    assert.ok(event, JSON.stringify(review.events));
    assert.match(event.label, /^cut [0-9.]+ mm\^2, 0\.0 mm\^2 off the marked line$/);
    // The scalpel's resistance is felt as one steady push, not a flicker: a stroke is a contact
    // or two in the review, not hundreds.
    const contacts = review.events.filter((e) => e.kind === 'contact' && e.hand === 0);
    assert.ok(contacts.length <= 6, `${contacts.length} contact events of the scalpel: ${JSON.stringify(contacts.slice(0, 10))}`);
    // The replay opens paused; the marker seeks it there.
    await sees(page.getByTestId('replay-play').filter({ hasText: 'Play' }), 'a replay that opens paused');
    const before = await canvas_state(page, 'replay-canvas');
    await cut.first().click();
    await wait_for_canvas(
      page,
      'replay-canvas',
      { after_frame: before.frame, time_min: event.t_s - 0.05, time_max: event.t_s + 0.5 },
      `the replay at the cut (${event.t_s} s)`,
      20_000,
    );
    await snap(page, 'instructor-review-liver');

    // The instructor may look from outside the body, even while the replay is paused.
    const camera = page.getByRole('group', { name: 'Camera' });
    await sees(camera, 'the camera switch');
    const scope_view = await canvas_state(page, 'replay-canvas');
    await camera.getByRole('button', { name: 'Outside view' }).click();
    await wait_for_canvas(page, 'replay-canvas', { after_frame: scope_view.frame }, 'a frame from outside');
    const outside_view = await canvas_state(page, 'replay-canvas');
    const moved = scope_view.grid.filter((v, i) => Math.abs(v - outside_view.grid[i]) > 8).length;
    assert.ok(moved > scope_view.grid.length / 4, `the outside view differs in ${moved} of ${scope_view.grid.length} samples`);
    assert.equal(outside_view.sim_time, scope_view.sim_time, 'the same instant, seen from outside');
    await snap(page, 'instructor-replay-outside');
  },
  { timeout_ms: 150_000 },
);
