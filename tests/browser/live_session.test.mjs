// Browser test of a live session and its replay against the real incise-server and the real
// incise-agent (node --test): what the trainee sees while training, then what an instructor sees
// when replaying the recording. Needs web/dist, the server and agent binaries; see support.mjs.
import assert from 'node:assert/strict';
import {
  api_call,
  browser_suite,
  canvas_state,
  click_for_response,
  demo,
  log_in,
  metric,
  region,
  sees,
  snap,
  wait_for_canvas,
} from './support.mjs';

const { scenario } = browser_suite({ time_zone: 'Asia/Kolkata', with_agent: true });


scenario(
  'a trainee trains live at a station, then an instructor replays and seeks the recording',
  async (page, env) => {
    // --- The trainee books the station for the current quarter hour and starts a session. ---
    const login = await log_in(page, demo.trainee);
    assert.equal(login.status(), 200);
    await page.waitForURL('**/trainee');

    const stations = await api_call(page, 'GET', '/api/stations');
    const station = stations.body.find((s) => s.name === 'Station 1');
    assert.ok(station, 'the demo data has Station 1');
    assert.equal(station.online, true, 'the agent started by the test is connected');

    // No booking covers now: the walk-up form books the slot in progress at the online station.
    const walk_up = region(page, 'Train now').getByRole('form', { name: 'Walk up to a station' });
    await sees(walk_up, 'the walk-up form when no booking covers now');
    assert.equal(await walk_up.getByLabel('Station').inputValue(), String(station.id), 'the online station is preselected');
    const booking = await click_for_response(page, walk_up.getByRole('button', { name: /^Book from / }), 'POST', /^\/api\/bookings$/);
    assert.equal(booking.status(), 201, `booking the slot covering now: ${await booking.text()}`);

    const curricula = await api_call(page, 'GET', '/api/curricula');
    const first_task = curricula.body[0].definition.modules[0].tasks[0];
    const start_form = region(page, 'Train now').getByRole('form', { name: 'Start a session at Station 1' });
    await sees(start_form, 'a form to start a session at the booked station');
    assert.equal(await start_form.getByLabel('Task').inputValue(), first_task.key, 'the first task is preselected');
    // A task whose prerequisite is not mastered is offered disabled, with the server's reason, and
    // the server refuses it whatever the page sends.
    const locked_option = start_form.getByLabel('Task', { exact: true }).locator('option', { hasText: 'Two-handed palpation (locked)' });
    await locked_option.waitFor({ state: 'attached' });
    assert.equal(await locked_option.isDisabled(), true, 'a locked task cannot be chosen');
    const reason = 'task "Two-handed palpation" is locked: master "Palpation" first';
    await sees(start_form.getByRole('list', { name: 'Prerequisites to master first' }).filter({ hasText: 'Task "Two-handed palpation" is locked: master "Palpation" first.' }), 'why it is locked');
    const refused = await api_call(page, 'POST', '/api/sessions', { station_id: station.id, task: 'bimanual_palpation' });
    assert.equal(refused.status, 409);
    assert.equal(refused.body.error, reason);

    const started = await click_for_response(
      page,
      start_form.getByRole('button', { name: 'Start session' }),
      'POST',
      /^\/api\/sessions$/,
    );
    assert.equal(started.status(), 201, await started.text());
    assert.deepEqual(started.request().postDataJSON(), { station_id: station.id, task: first_task.key });
    const session = await started.json();
    await page.waitForURL(`**/sessions/${session.id}`);

    // --- The live picture: frames keep coming (so acks work) and the picture changes. ---
    await wait_for_canvas(page, 'live-canvas', {}, 'a first live frame');
    await sees(metric(page, 'state').filter({ hasText: 'Running' }), 'the state Running');
    await sees(metric(page, 'agent_online').filter({ hasText: 'Online' }), 'the station agent online');
    // The pace is the server's: a real-time factor, and "behind" only when the server says so.
    await sees(metric(page, 'pace').filter({ hasText: /^\d+\.\d\dx real time/ }), 'the pace as a real-time factor');
    const first = await canvas_state(page, 'live-canvas');
    assert.ok(
      Math.max(...first.grid) - Math.min(...first.grid) > 20,
      'the first frame is a picture, not a uniform fill',
    );
    await page.waitForTimeout(2_500);
    const second = await canvas_state(page, 'live-canvas');
    // The server keeps at most two frames unacknowledged, so many more frames mean acks arrive.
    assert.ok(second.frame >= first.frame + 10, `frames advanced from ${first.frame} to ${second.frame} in 2.5 s`);
    assert.ok(second.sim_time > first.sim_time, `sim time advanced from ${first.sim_time} to ${second.sim_time}`);
    const changed = first.grid.filter((v, i) => Math.abs(v - second.grid[i]) > 8).length;
    assert.ok(changed >= 10, `the picture changed in ${changed} of ${first.grid.length} sampled pixels`);
    // The page's meter counts the frames drawn in the last second: a positive rate shows within a
    // few seconds even on a loaded machine (where a second without a frame reads 0.0).
    await sees(metric(page, 'fps').filter({ hasText: /^(?!0\.0$)\d+\.\d$/ }), 'a positive frame rate');
    // The agent's link report arrives once a second: the haptic loop at about 1 kHz, a round
    // trip, and device 0 with its model age.
    await sees(metric(page, 'haptic_loop').filter({ hasText: / Hz$/ }), 'the haptic loop rate');
    const loop_hz = Number((await metric(page, 'haptic_loop').textContent()).replace(' Hz', ''));
    assert.ok(loop_hz > 500, `haptic loop ${loop_hz} Hz`);
    await sees(metric(page, 'link').filter({ hasText: /^round trip [0-9.]+ ms/ }), 'the link round trip');
    await sees(metric(page, 'haptic_devices').filter({ hasText: /^0: [0-9]+ ms/ }), 'device 0 in the link report');

    // --- Meanwhile an instructor, in their own browser, finds the session live and watches. ---
    const watcher_context = await env.browser.newContext({ baseURL: env.server.url, viewport: { width: 1366, height: 800 } });
    try {
      const watcher = await watcher_context.newPage();
      assert.equal((await log_in(watcher, demo.instructor)).status(), 200);
      await watcher.waitForURL('**/instructor');
      await region(watcher, 'Live now').getByRole('link', { name: `Watch session ${session.id} live` }).click();
      await watcher.waitForURL(`**/sessions/${session.id}`);
      await wait_for_canvas(watcher, 'live-canvas', {}, "the instructor's first live frame");
      await snap(watcher, 'instructor-live-watch');
    } finally {
      await watcher_context.close();
    }

    // Long enough a session that the middle of its recording is far from its start, and that the
    // looping 20 s script of the simulated device touches the tissue in it wherever it started
    // (its longest stretch off the tissue is under 8 s).
    await wait_for_canvas(page, 'live-canvas', { time_min: 12 }, 'twelve simulated seconds', 40_000);
    await snap(page, 'trainee-live-session');
    page.once('dialog', (dialog) => dialog.accept());
    const stopped = await click_for_response(
      page,
      page.getByRole('button', { name: 'Stop' }),
      'POST',
      new RegExp(`^/api/sessions/${session.id}/stop$`),
    );
    assert.equal(stopped.status(), 200, await stopped.text());
    const stop_time = (await canvas_state(page, 'live-canvas')).sim_time;
    await sees(page.getByRole('status').filter({ hasText: 'The session has ended' }), 'that the session has ended');

    const result = region(page, 'Result');
    const recording_link = result.getByRole('link', { name: 'Watch the recording of this session' });
    await sees(recording_link, 'a link to the recording');
    const recording_id = Number(/^\/recordings\/(\d+)$/.exec(await recording_link.getAttribute('href'))?.[1]);
    assert.ok(recording_id > 0, 'the link names the recording');
    const scores = (await api_call(page, 'GET', '/api/scores')).body.filter((s) => s.session_id === session.id);
    assert.ok(scores.length > 0, 'stopping stored the scores of the session');
    // Each metric by its name and key, against its threshold; the completion criteria apart.
    const metrics = (await api_call(page, 'GET', '/api/metrics')).body;
    const criteria = result.getByRole('region', { name: 'Completion criteria' });
    for (const score of scores) {
      const name = metrics.find((m) => m.key === score.metric)?.name;
      assert.ok(name, `the catalogue names ${score.metric}`);
      const shown = score.criterion ? criteria.getByRole('listitem') : result.getByRole('row');
      await sees(shown.filter({ hasText: name }).filter({ hasText: score.criterion ? '' : score.metric }), `the score "${score.metric}" in the result`);
    }
    await sees(result.getByTestId('attempt-standing').filter({ hasText: /^Palpation: \d of 3 passes in a row/ }), 'where the trainee stands');
    await snap(page, 'trainee-session-result');

    // --- The instructor opens the recording from the recordings list. ---
    await click_for_response(page, page.getByRole('button', { name: 'Log out' }), 'POST', /^\/api\/logout$/);
    await page.waitForURL('**/login');
    assert.equal((await log_in(page, demo.instructor)).status(), 200);
    await page.waitForURL('**/instructor');
    await region(page, 'Recordings')
      .getByRole('link', { name: `Replay the recording of session ${session.id}` })
      .click();
    await page.waitForURL(`**/recordings/${recording_id}`);

    // Slow motion, so that the replay's own progress cannot be mistaken for the seek. The
    // controls are enabled once the first metrics arrive, i.e. once the socket is open.
    await page.getByTestId('replay-speed').selectOption('0.25');
    await wait_for_canvas(page, 'replay-canvas', {}, 'a first replay frame');
    // It opens paused on its first picture: the button offers Play, and the time stands still.
    const play = page.getByTestId('replay-play');
    await sees(play.filter({ hasText: 'Play' }), 'the Play button of a replay that opens paused');
    const opened = await canvas_state(page, 'replay-canvas');
    await page.waitForTimeout(1_000);
    const still = await canvas_state(page, 'replay-canvas');
    assert.equal(still.sim_time, opened.sim_time, 'a replay opens paused');
    assert.ok(opened.sim_time < 0.1, `it opens at the start, not at ${opened.sim_time} s`);
    const seek = page.getByTestId('replay-seek');
    const duration = Number(await seek.getAttribute('max'));
    // The replay lasts exactly what the recording stored. The last live frame the trainee saw
    // came at or before the stop; how long before depends on how busy the machine was (frames are
    // dropped, never the simulation), so it bounds the duration from below only.
    const recording = (await api_call(page, 'GET', '/api/recordings')).body.find((r) => r.id === recording_id);
    assert.ok(recording, 'the instructor sees the recording in the list');
    assert.ok(Math.abs(duration - recording.duration_s) < 1e-6, `the replay lasts ${duration} s; the recording ${recording.duration_s} s`);
    assert.ok(stop_time <= duration + 0.01 && duration - stop_time < 5, `the replay lasts ${duration} s; the last live frame was at ${stop_time} s`);

    const target = Math.round((duration / 2) * 10) / 10;
    const before_seek = await canvas_state(page, 'replay-canvas');
    assert.ok(before_seek.sim_time < target - 1, `the replay is at ${before_seek.sim_time} s before seeking to ${target} s`);
    await seek.fill(String(target));
    // Paused, the seek lands on its target and stays there; "Seeking to …" is gone once it has.
    await wait_for_canvas(
      page,
      'replay-canvas',
      { after_frame: before_seek.frame, time_min: target - 0.05, time_max: target + 0.05 },
      `the replay at ${target} s after the seek`,
    );
    await page.getByTestId('replay-seeking').waitFor({ state: 'detached' });
    assert.ok(Math.abs(Number(await seek.inputValue()) - target) <= 0.1, 'the slider stays at the target');

    // Play runs on from there; Pause stops it: the button follows the server's "playing", and the
    // picture's time stands still.
    await play.click();
    await sees(play.filter({ hasText: 'Pause' }), 'the Pause button of a playing replay');
    await wait_for_canvas(page, 'replay-canvas', { time_min: target + 0.2 }, 'the replay playing on from the seek');
    await play.click();
    await sees(play.filter({ hasText: 'Play' }), 'the Play button of a paused replay');
    await page.waitForTimeout(300); // a frame received before the pause may still be decoding
    const paused_at = (await canvas_state(page, 'replay-canvas')).sim_time;
    await page.waitForTimeout(1_000);
    assert.equal((await canvas_state(page, 'replay-canvas')).sim_time, paused_at, 'a paused replay does not advance');

    // --- Review: an event marker jumps the replay to its event. ---
    const review = (await api_call(page, 'GET', `/api/sessions/${session.id}/review`)).body;
    assert.ok(review.events.some((e) => e.kind === 'contact'), `the probe touched the tissue: ${JSON.stringify(review.events)}`);
    // The event farthest from where the replay stands, so that the jump cannot be mistaken for it.
    const event = review.events.reduce((far, e) => (Math.abs(e.t_s - paused_at) > Math.abs(far.t_s - paused_at) ? e : far));
    assert.ok(Math.abs(event.t_s - paused_at) > 1, `an event ${event.t_s} s away from the replay's ${paused_at} s`);
    const markers = region(page, 'Events').getByTestId('event-marker');
    await sees(markers, 'the event markers');
    assert.equal(await markers.count(), review.events.length, 'one marker per event');
    await sees(page.getByTestId('timeline-force').locator('canvas'), 'the force timeline');
    await sees(page.getByTestId('timeline-damage').locator('canvas'), 'the damage timeline');
    const before_jump = await canvas_state(page, 'replay-canvas');
    await markers.filter({ hasText: `${event.t_s.toFixed(1)} s` }).first().click();
    await wait_for_canvas(
      page,
      'replay-canvas',
      { after_frame: before_jump.frame, time_min: event.t_s - 0.05, time_max: event.t_s + 0.5 },
      `the replay at the ${event.kind} marker (${event.t_s} s)`,
    );
    await snap(page, 'instructor-review');

    // --- An annotation at the replay's position, and a score adjustment with a reason. ---
    const at = (await canvas_state(page, 'replay-canvas')).sim_time;
    const notes = region(page, 'Annotations');
    await notes.getByLabel(/^Note at /).fill('Approach the tissue more slowly here.');
    const noted = await click_for_response(
      page,
      notes.getByRole('button', { name: 'Add annotation' }),
      'POST',
      new RegExp(`^/api/sessions/${session.id}/annotations$`),
    );
    assert.equal(noted.status(), 201, await noted.text());
    assert.ok(Math.abs(noted.request().postDataJSON().t_s - at) < 0.5, 'the note is at the replay position');
    await sees(notes.getByTestId('annotations').filter({ hasText: 'Approach the tissue more slowly here.' }), 'the new annotation');

    const adjust = region(page, 'Score adjustments');
    await adjust.getByLabel('Result').selectOption('fail');
    await adjust.getByLabel('Reason').fill('Rushed the approach; repeat with a slower descent.');
    const adjusted = await click_for_response(
      page,
      adjust.getByRole('button', { name: 'Adjust score' }),
      'POST',
      new RegExp(`^/api/sessions/${session.id}/adjustments$`),
    );
    assert.equal(adjusted.status(), 201, await adjusted.text());
    await sees(adjust.getByTestId('adjustments').filter({ hasText: '(in force)' }), 'the adjustment in force');
    await snap(page, 'instructor-review-notes');

    // The instructor's overview counts the adjusted attempt as not passed.
    await page.goto('/instructor');
    const overview = page.getByTestId('progress-overview');
    await sees(overview, "the trainees' progress at a glance");
    const trainee_row = (await api_call(page, 'GET', '/api/trainees/progress')).body.find((t) => t.username === demo.trainee.username);
    const palpation = trainee_row.tasks.find((t) => t.key === session.task);
    assert.equal(palpation.consecutive_passes, 0, `the adjusted attempt breaks the run: ${JSON.stringify(palpation)}`);
    assert.equal(palpation.passed_attempts, 0);
    await sees(
      overview.getByRole('row').filter({ hasText: trainee_row.display_name }).filter({ hasText: `0/${palpation.required_passes} in a row` }),
      "the trainee's palpation at 0 passes in a row",
    );
    await snap(page, 'instructor-home');
  },
  { timeout_ms: 150_000 },
);

/**
 * The trainee starts a session of the preselected task at the demo station (booking the slot in
 * progress first when no booking covers now), trains for `seconds` of simulated time and stops.
 * Returns the session and the verdict shown in its result.
 */
async function train_once(page, seconds) {
  await page.goto('/trainee');
  const train = region(page, 'Train now');
  const walk_up = train.getByRole('form', { name: 'Walk up to a station' });
  const start_form = train.getByRole('form', { name: 'Start a session at Station 1' });
  await sees(walk_up.or(start_form), 'the walk-up or the start form');
  if (await walk_up.isVisible()) {
    const booking = await click_for_response(page, walk_up.getByRole('button', { name: /^Book from / }), 'POST', /^\/api\/bookings$/);
    assert.equal(booking.status(), 201, await booking.text());
  }
  const started = await click_for_response(page, start_form.getByRole('button', { name: 'Start session' }), 'POST', /^\/api\/sessions$/);
  assert.equal(started.status(), 201, await started.text());
  const session = await started.json();
  await page.waitForURL(`**/sessions/${session.id}`);
  await wait_for_canvas(page, 'live-canvas', { time_min: seconds }, `${seconds} simulated seconds`, (seconds + 20) * 1000);
  page.once('dialog', (dialog) => dialog.accept());
  const stopped = await click_for_response(page, page.getByRole('button', { name: 'Stop' }), 'POST', new RegExp(`^/api/sessions/${session.id}/stop$`));
  assert.equal(stopped.status(), 200, await stopped.text());
  const verdict = region(page, 'Result').getByTestId('attempt-verdict');
  await sees(verdict, 'the verdict of the attempt');
  return { session, verdict: await verdict.textContent() };
}

scenario(
  'a trainee masters palpation over consecutive passing attempts and the two-handed task unlocks',
  async (page) => {
    assert.equal((await log_in(page, demo.trainee)).status(), 200);
    await page.waitForURL('**/trainee');
    const curriculum = region(page, 'My curriculum');
    await sees(curriculum.getByTestId('task-status-bimanual_palpation').filter({ hasText: 'Locked' }), 'the two-handed task locked');
    const required = (await api_call(page, 'GET', '/api/progress')).body.tasks.find((t) => t.key === 'palpation').required_passes;
    // Stopped after a second, the attempt has not done the task (the tools barely touched the
    // tissue, no landmark reached): it fails on its completion criteria, and says so.
    const { verdict: undone } = await train_once(page, 1);
    assert.match(undone, /^Not passed: the task was not done \(.*tools on the tissue/, undone);
    await sees(
      region(page, 'Result').getByRole('region', { name: 'Completion criteria' }).getByRole('listitem').filter({ hasText: /^Not met Tools on the tissue/ }),
      'the contact criterion not met',
    );
    // The simulated device loops a 20 s script that touches the tissue for about 8 s, visits the
    // three landmarks and crosses the nerve once: a 21 s attempt passes every threshold.
    for (let attempt = 1; attempt <= required; ++attempt) {
      const { verdict } = await train_once(page, 21);
      assert.match(verdict, /^Passed/, `attempt ${attempt}: ${verdict}`);
      const progress = (await api_call(page, 'GET', '/api/progress')).body.tasks;
      const palpation = progress.find((t) => t.key === 'palpation');
      const next = progress.find((t) => t.key === 'bimanual_palpation');
      assert.ok(palpation.consecutive_passes >= attempt, `after attempt ${attempt}: ${JSON.stringify(palpation)}`);
      assert.equal(next.unlocked, palpation.mastered, 'the next task unlocks exactly when palpation is mastered');
    }
    await page.goto('/trainee');
    await sees(curriculum.getByTestId('task-status-palpation').filter({ hasText: 'Mastered' }), 'palpation mastered');
    await sees(curriculum.getByTestId('task-status-bimanual_palpation').filter({ hasText: /^(Unlocked|In progress)$/ }), 'the two-handed task unlocked');
    await snap(page, 'trainee-mastered');
  },
  { timeout_ms: 240_000 },
);

/** The trainee's progress chart on palpation's completion time: the sentence under it. */
async function palpation_time_summary(page) {
  assert.equal((await log_in(page, demo.trainee)).status(), 200);
  await page.waitForURL('**/trainee');
  const chart = page.getByTestId('progress-chart');
  await sees(chart.getByTestId('progress-task'), 'the progress chart');
  await chart.getByTestId('progress-task').selectOption('palpation');
  await chart.getByTestId('progress-metric').selectOption('completion_time_s');
  const summary = chart.getByTestId('progress-summary');
  await sees(summary.filter({ hasText: 'experts' }), "the experts' band in the chart's summary");
  const text = await summary.textContent();
  await click_for_response(page, page.getByRole('button', { name: 'Log out' }), 'POST', /^\/api\/logout$/);
  return text;
}

scenario(
  "an instructor records an expert run at the station, and the experts' band in the trainee's chart takes it in",
  async (page) => {
    const before_summary = await palpation_time_summary(page);

    assert.equal((await log_in(page, demo.instructor)).status(), 200);
    await page.waitForURL('**/instructor');
    const expert_runs = async () =>
      (await api_call(page, 'GET', '/api/benchmarks')).body.find((b) => b.task === 'palpation' && b.metric === 'completion_time_s')?.n ?? 0;
    const runs_before = await expert_runs();
    const form = region(page, 'Run a task').getByRole('form', { name: 'Run a task at Station 1' });
    await sees(form.getByRole('button', { name: 'Start session' }), 'the form to run a task at Station 1');
    await form.locator('option[value="palpation"]').waitFor({ state: 'attached' });
    assert.equal(await form.getByLabel('Task', { exact: true }).inputValue(), 'palpation', 'palpation offered first');
    await form.getByTestId('start-expert').check();
    const started = await click_for_response(page, form.getByRole('button', { name: 'Start session' }), 'POST', /^\/api\/sessions$/);
    assert.equal(started.status(), 201, await started.text());
    assert.equal(started.request().postDataJSON().expert, true, 'started as an expert run');
    const session = await started.json();
    await page.waitForURL(`**/sessions/${session.id}`);
    await wait_for_canvas(page, 'live-canvas', { time_min: 5 }, '5 simulated seconds', 30_000);
    page.once('dialog', (dialog) => dialog.accept());
    const stopped = await click_for_response(page, page.getByRole('button', { name: 'Stop' }), 'POST', new RegExp(`^/api/sessions/${session.id}/stop$`));
    assert.equal(stopped.status(), 200, await stopped.text());
    assert.equal(await expert_runs(), runs_before + 1, 'the run joined the benchmark');
    await click_for_response(page, page.getByRole('button', { name: 'Log out' }), 'POST', /^\/api\/logout$/);

    // The band the trainee compares against now holds the new run: its mean moved.
    const after_summary = await palpation_time_summary(page);
    assert.notEqual(after_summary, before_summary, `the experts' band changed: ${before_summary} / ${after_summary}`);
  },
  { timeout_ms: 120_000 },
);
