// Browser test of the dashboard against the real incise-server (node --test).
// Each scenario asserts what a person sees, and the API status behind it where that matters.
// Needs web/dist (npm run build in web/) and the server binary; see support.mjs.
import assert from 'node:assert/strict';
import { api_call, browser_suite, click_for_response, demo, log_in, region, sees, snap } from './support.mjs';

// The browser runs in a zone with a half-hour offset and no daylight saving, so that the local
// time shown and the UTC time sent are different and predictable.
const time_zone = 'Asia/Kolkata'; // UTC+05:30

const { env, scenario } = browser_suite({ time_zone });

/** Opens one area of the administration from its own navigation, as an admin would. */
async function admin_area(page, title) {
  await page.getByRole('navigation', { name: 'Administration' }).getByRole('link', { name: title, exact: true }).click();
  await page.waitForFunction((t) => document.title === `${t} · Administration · Incise`, title);
}

/** "YYYY-MM-DD" of tomorrow in the browser's zone. */
function tomorrow_in_zone() {
  return new Intl.DateTimeFormat('en-CA', { timeZone: time_zone }).format(new Date(Date.now() + 24 * 3600 * 1000));
}

scenario('a trainee books a slot, meets a conflict and cancels', async (page) => {
  const login = await log_in(page, demo.trainee);
  assert.equal(login.status(), 200);
  const { user } = await login.json();
  await page.waitForURL('**/trainee');
  const header = page.getByRole('banner');
  await sees(header.getByText(user.display_name, { exact: true }), 'the display name in the header');
  await sees(header.getByText('Trainee', { exact: true }), 'the role in the header');
  await sees(header.getByRole('button', { name: 'Log out' }), 'a Log out button');

  // The curriculum: the first task is open, the two-handed one waits for it to be mastered.
  const curriculum = region(page, 'My curriculum');
  await sees(curriculum.getByTestId('task-status-palpation').filter({ hasText: /^(Unlocked|In progress)$/ }), 'palpation open');
  await sees(curriculum.getByTestId('task-status-bimanual_palpation').filter({ hasText: 'Locked' }), 'the two-handed task locked');
  await sees(curriculum.getByTestId('task-passes-palpation').filter({ hasText: / of 3$/ }), 'passes in a row out of 3');

  const form = page.getByRole('form', { name: 'Book a slot' });
  const station_select = form.getByLabel('Station', { exact: true });
  const station_option = station_select.locator('option', { hasText: 'Station 1' });
  await station_option.waitFor({ state: 'attached' });
  await station_select.selectOption(await station_option.getAttribute('value'));
  const date = tomorrow_in_zone();
  await form.getByLabel('Date', { exact: true }).fill(date);
  await form.getByLabel('Start time', { exact: true }).selectOption('10:00');
  await form.getByLabel('Duration', { exact: true }).selectOption('60');
  const booked = await click_for_response(page, form.getByRole('button', { name: 'Book slot' }), 'POST', /^\/api\/bookings$/);
  assert.equal(booked.status(), 201, await booked.text());
  // 10:00 in UTC+05:30 is 04:30Z.
  assert.deepEqual(
    { starts_at: booked.request().postDataJSON().starts_at, ends_at: booked.request().postDataJSON().ends_at },
    { starts_at: `${date}T04:30:00Z`, ends_at: `${date}T05:30:00Z` },
  );
  assert.equal(booked.request().headers()['content-type'], 'application/json');

  const bookings = region(page, 'My bookings');
  const first_row = bookings.getByRole('row').filter({ hasText: 'Station 1' }).filter({ hasText: '10:00–11:00' });
  await sees(first_row.filter({ hasText: 'Active' }), 'the new booking listed as active');

  await form.getByLabel('Start time', { exact: true }).selectOption('10:30');
  await form.getByLabel('Duration', { exact: true }).selectOption('30');
  const conflict = await click_for_response(page, form.getByRole('button', { name: 'Book slot' }), 'POST', /^\/api\/bookings$/);
  assert.equal(conflict.status(), 409);
  const { error: conflict_message } = await conflict.json();
  // The dashboard shows the server's message with any UTC times in it rewritten in local time.
  const utc_time = /\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}Z/g;
  let conflict_alert = form.getByRole('alert');
  for (const part of conflict_message.split(utc_time).filter((p) => p.trim())) {
    conflict_alert = conflict_alert.filter({ hasText: part.trim() });
  }
  if (conflict_message.match(utc_time)) conflict_alert = conflict_alert.filter({ hasText: '10:00' });
  await sees(conflict_alert, `the conflict message "${conflict_message}"`);
  assert.equal(await bookings.getByRole('row').filter({ hasText: '10:30–11:00' }).count(), 0, 'the overlapping slot was not listed');

  page.once('dialog', (dialog) => dialog.accept());
  const cancelled = await click_for_response(page, first_row.getByRole('button', { name: /^Cancel/ }), 'DELETE', /^\/api\/bookings\/\d+$/);
  assert.equal(cancelled.status(), 204);
  await sees(first_row.filter({ hasText: 'Cancelled' }), 'the booking shown as cancelled');
  assert.equal(await first_row.getByRole('button', { name: /^Cancel/ }).count(), 0, 'a cancelled booking has no Cancel button');
});

scenario('a wrong password shows the error on the login page', async (page) => {
  const response = await log_in(page, { username: 'trainee', password: 'not-the-password' });
  assert.equal(response.status(), 401);
  assert.equal((await response.json()).error, 'wrong username or password');
  await sees(page.getByRole('alert').filter({ hasText: 'wrong username or password' }), 'the login error');
  assert.equal(new URL(page.url()).pathname, '/login');
});

scenario('an admin creates a user, who can then log in', async (page) => {
  const login = await log_in(page, demo.admin);
  assert.equal(login.status(), 200);
  await page.waitForURL('**/admin/users');

  const username = `ins-${Date.now().toString(36)}`;
  const display_name = `Dr ${username}`;
  const password = 'correct-horse-battery';
  const form = page.getByRole('form', { name: 'Create user' });
  const create = async () => {
    await form.getByLabel('Username', { exact: true }).fill(username);
    await form.getByLabel('Display name', { exact: true }).fill(display_name);
    await form.getByLabel('Role', { exact: true }).selectOption('instructor');
    await form.getByLabel('Password', { exact: true }).fill(password);
    return click_for_response(page, form.getByRole('button', { name: 'Create user' }), 'POST', /^\/api\/users$/);
  };

  const created = await create();
  assert.equal(created.status(), 201, await created.text());
  const users = region(page, 'Users');
  // The row whose username cell is the new user's (trainees' rows name every instructor too).
  const user_row = users.getByRole('row').filter({ has: page.getByRole('cell', { name: username, exact: true }) });
  await sees(user_row.filter({ hasText: 'Instructor' }), 'the new user in the users list');

  const duplicate = await create();
  assert.equal(duplicate.status(), 409);
  const { error: duplicate_message } = await duplicate.json();
  await sees(form.getByRole('alert').filter({ hasText: duplicate_message }), `the duplicate message "${duplicate_message}"`);
  assert.equal(await user_row.count(), 1, 'the user is listed once');

  await click_for_response(page, page.getByRole('button', { name: 'Log out' }), 'POST', /^\/api\/logout$/);
  await page.waitForURL('**/login');
  await sees(page.getByRole('button', { name: 'Log in' }), 'the login page after logging out');

  const new_login = await log_in(page, { username, password });
  assert.equal(new_login.status(), 200);
  await page.waitForURL('**/instructor');
  await sees(page.getByRole('banner').getByText(display_name, { exact: true }), "the new user's name in the header");
  await sees(page.getByRole('heading', { name: 'Sessions & bookings' }), "the instructor's page");
});

scenario('a trainee cannot open the admin page', async (page) => {
  const login = await log_in(page, demo.trainee);
  assert.equal(login.status(), 200);
  await page.waitForURL('**/trainee');
  await page.goto('/admin');
  await sees(page.getByRole('heading', { name: 'Access denied' }), 'the access-denied message');
  assert.equal(await page.getByRole('form', { name: 'Create user' }).count(), 0, 'no admin form is shown');
  const status = await page.evaluate(() => fetch('/api/users', { credentials: 'same-origin' }).then((r) => r.status));
  assert.equal(status, 403, 'GET /api/users as a trainee');
});

scenario('an admin edits a pass threshold and downloads the scores as CSV', async (page) => {
  const login = await log_in(page, demo.admin);
  assert.equal(login.status(), 200);
  await page.waitForURL('**/admin/users');
  await admin_area(page, 'Curricula');

  const editor = page.getByRole('form', { name: 'Pass thresholds' });
  // Named as people read them, entered in the unit shown (a cut's area in mm², not m²).
  const peak = editor.getByLabel('Peak force at most', { exact: true }).first();
  await sees(peak, 'the palpation peak force threshold');
  assert.equal(await peak.inputValue(), '4', 'the demo threshold is 4 N');
  assert.equal(await editor.getByLabel('Cut area at least', { exact: true }).first().inputValue(), '60', 'the liver cut asks for 60 mm²');

  await peak.fill('3.5');
  const saved = await click_for_response(page, editor.getByRole('button', { name: 'Save thresholds' }), 'PUT', /^\/api\/curricula\/\d+$/);
  assert.equal(saved.status(), 200, await saved.text());
  await sees(editor.getByRole('status').filter({ hasText: 'Thresholds saved.' }), 'the saved message');
  const sent = saved.request().postDataJSON();
  assert.equal(sent.modules[0].tasks[0].metrics[2].threshold.value, 3.5, 'the edited value was sent');

  // It sticks: after a reload the field shows it, and the curriculum the server holds has it.
  await page.reload();
  await sees(editor.getByLabel('Peak force at most', { exact: true }).first(), 'the threshold field after a reload');
  assert.equal(await editor.getByLabel('Peak force at most', { exact: true }).first().inputValue(), '3.5');

  // The scores export downloads as CSV with its header row.
  await admin_area(page, 'Exports');
  const exports = region(page, 'Exports');
  const csv = await page.evaluate(async (href) => {
    const response = await fetch(href, { credentials: 'same-origin' });
    return { status: response.status, type: response.headers.get('content-type'), text: await response.text() };
  }, await exports.getByRole('link', { name: 'Scores and attempts (CSV)' }).getAttribute('href'));
  assert.equal(csv.status, 200);
  assert.equal(csv.type, 'text/csv; charset=utf-8');
  assert.ok(csv.text.startsWith('score_id,session_id,trainee,task,metric,value,unit,passed,created_at\r\n'), csv.text.slice(0, 80));

  // Back to the demo threshold for the other scenarios.
  await admin_area(page, 'Curricula');
  await editor.getByLabel('Peak force at most', { exact: true }).first().fill('4');
  const restored = await click_for_response(page, editor.getByRole('button', { name: 'Save thresholds' }), 'PUT', /^\/api\/curricula\/\d+$/);
  assert.equal(restored.status(), 200);
});

scenario('a trainee books from the station calendar, meets a clear conflict and follows their progress', async (page) => {
  assert.equal((await log_in(page, demo.trainee)).status(), 200);
  await page.waitForURL('**/trainee');
  const calendar = region(page, 'Station calendar');
  await sees(calendar.getByTestId('booking-calendar'), 'the station calendar');
  const station_select = calendar.getByLabel('Station', { exact: true });
  await station_select.selectOption(await station_select.locator('option', { hasText: 'Station 1' }).getAttribute('value'));
  // Next week's Tuesday is in the future whatever today is.
  await calendar.getByRole('button', { name: 'Next week' }).click();

  const booked = await click_for_response(
    page,
    calendar.getByRole('button', { name: 'Book Station 1 Tuesday 10:00-10:30', exact: true }),
    'POST',
    /^\/api\/bookings$/,
  );
  assert.equal(booked.status(), 201, await booked.text());
  const mine = await booked.json();
  // 10:00 in UTC+05:30 is 04:30Z, half an hour long.
  assert.match(mine.starts_at, /T04:30:00Z$/);
  assert.equal(Date.parse(mine.ends_at) - Date.parse(mine.starts_at), 30 * 60 * 1000);
  await sees(calendar.getByRole('button', { name: 'Cancel my booking Station 1 Tuesday 10:00' }), 'the slot shown as mine');

  // Someone else books 11:00 meanwhile (an instructor, in their own browser); the trainee's
  // calendar still offers it, and booking it shows the server's conflict.
  const other = await env.browser.newContext({ baseURL: env.server.url });
  const other_page = await other.newPage();
  assert.equal((await log_in(other_page, demo.instructor)).status(), 200);
  const eleven = new Date(Date.parse(mine.starts_at) + 3600 * 1000);
  const taken = await other_page.evaluate(
    async (body) => {
      const response = await fetch('/api/bookings', {
        method: 'POST',
        headers: { 'Content-Type': 'application/json' },
        body: JSON.stringify(body),
      });
      return { status: response.status, text: await response.text() };
    },
    {
      station_id: mine.station_id,
      starts_at: eleven.toISOString().replace('.000Z', 'Z'),
      ends_at: new Date(eleven.getTime() + 1800 * 1000).toISOString().replace('.000Z', 'Z'),
    },
  );
  await other.close();
  assert.equal(taken.status, 201, taken.text);
  const conflict = await click_for_response(
    page,
    calendar.getByRole('button', { name: 'Book Station 1 Tuesday 11:00-11:30', exact: true }),
    'POST',
    /^\/api\/bookings$/,
  );
  assert.equal(conflict.status(), 409);
  await sees(calendar.getByRole('alert').filter({ hasText: /^Could not book the slot: .*already booked/ }), 'the conflict in the calendar');
  // The calendar reloads and shows the slot taken, without saying by whom.
  const taken_cell = calendar.getByTestId(`slot-${mine.station_id}-${eleven.toISOString().replace('.000Z', 'Z')}`);
  await sees(taken_cell.filter({ hasText: /^Taken$/ }), 'the 11:00 slot taken');
  await snap(page, 'trainee-calendar-conflict');

  // Cancel from the calendar: the slot is free again.
  const cancelled = await click_for_response(
    page,
    calendar.getByRole('button', { name: 'Cancel my booking Station 1 Tuesday 10:00' }),
    'DELETE',
    /^\/api\/bookings\/\d+$/,
  );
  assert.equal(cancelled.status(), 204);
  await sees(calendar.getByRole('button', { name: 'Book Station 1 Tuesday 10:00-10:30', exact: true }), 'the slot free again');

  // The progress chart draws the demo attempt, with its numbers readable as a table.
  const progress = region(page, 'My progress over attempts');
  await sees(progress.getByTestId('progress-chart').locator('canvas'), 'the progress chart');
  // One row per attempt at the chosen task that scored the chosen metric.
  const scores = await page.evaluate(async () => (await fetch('/api/scores')).json());
  const task = await progress.getByTestId('progress-task').inputValue();
  const metric = await progress.getByTestId('progress-metric').inputValue();
  const attempts = scores.filter((s) => s.task === task && s.metric === metric);
  assert.ok(attempts.length > 0, `the chart's ${task} / ${metric} is among the trainee's scores`);
  await progress.getByText('Show the numbers').click();
  const table = progress.getByTestId('progress-table');
  await sees(table.getByRole('row').nth(1), 'the first attempt in the table');
  assert.equal(await table.getByRole('row').count(), attempts.length + 1, 'a header and one row per attempt');
  await snap(page, 'trainee-home');
});

scenario('an admin imports a curriculum, calibrates a station and assigns instructors, each with clear errors, and reads the audit log', async (page) => {
  assert.equal((await log_in(page, demo.admin)).status(), 200);
  await page.waitForURL('**/admin/users');
  await admin_area(page, 'Curricula');

  // A curriculum file with a wrong threshold operator: the server names the path of the problem.
  const curriculum = {
    name: 'Suturing basics',
    description: 'Interrupted sutures on a pad.',
    modules: [
      {
        key: 'suturing',
        name: 'Suturing',
        tasks: [
          {
            key: 'single_stitch',
            name: 'Single stitch',
            scene: 'scenes/palpation.json',
            metrics: [{ key: 'completion_time_s', threshold: { op: '<', value: 90 }, unit: 's' }],
            consecutive_passes_required: 2,
          },
        ],
      },
    ],
  };
  const importer = page.getByTestId('curriculum-import');
  const upload = async (body) => {
    await importer.getByLabel('Curriculum file').setInputFiles({ name: 'suturing.json', mimeType: 'application/json', buffer: Buffer.from(JSON.stringify(body)) });
    return click_for_response(page, importer.getByRole('button', { name: 'Import curriculum' }), 'POST', /^\/api\/curricula$/);
  };
  const refused = await upload(curriculum);
  assert.equal(refused.status(), 422);
  const { error } = await refused.json();
  assert.match(error, /^modules\[0\]\.tasks\[0\]\.metrics\[0\]\.threshold\.op: /);
  await sees(importer.getByRole('alert').filter({ hasText: error }), 'the path of the problem in the file');
  curriculum.modules[0].tasks[0].metrics[0].threshold.op = '<=';
  const imported = await upload(curriculum);
  assert.equal(imported.status(), 201, await imported.text());
  await sees(importer.getByRole('status').filter({ hasText: 'Imported “Suturing basics”.' }), 'the import confirmed');

  // The curriculum editor: a prerequisite naming no task is refused with its path; the stored
  // definition, saved back unchanged, is accepted.
  const editor = page.getByTestId('curriculum-editor');
  await editor.getByLabel('Curriculum', { exact: true }).selectOption({ label: 'Basic laparoscopic skills' });
  const json_text = editor.getByLabel('Curriculum JSON');
  await page.waitForFunction(() => document.querySelector('[aria-label="Curriculum JSON"]')?.value.includes('Basic laparoscopic skills'));
  const stored = await json_text.inputValue();
  const broken = JSON.parse(stored);
  broken.modules[0].tasks[1].prerequisites = ['suturing_101'];
  await json_text.fill(JSON.stringify(broken, null, 2));
  const rejected = await click_for_response(page, editor.getByRole('button', { name: 'Save curriculum' }), 'PUT', /^\/api\/curricula\/\d+$/);
  assert.equal(rejected.status(), 422);
  const { error: edit_error } = await rejected.json();
  assert.equal(edit_error, 'modules[0].tasks[1].prerequisites[0]: unknown task "suturing_101"');
  await sees(editor.getByRole('alert').filter({ hasText: edit_error }), 'the path of the problem in the edit');
  await json_text.fill(stored);
  const kept = await click_for_response(page, editor.getByRole('button', { name: 'Save curriculum' }), 'PUT', /^\/api\/curricula\/\d+$/);
  assert.equal(kept.status(), 200, await kept.text());
  await sees(editor.getByRole('status').filter({ hasText: 'Saved “Basic laparoscopic skills”.' }), 'the curriculum saved');

  // A calibration the server refuses, then the one it had, saved back, in the power users' JSON.
  await admin_area(page, 'Stations');
  const calibration = page.getByTestId('calibration-editor');
  await calibration.getByText('Edit as JSON').click();
  const text = calibration.getByLabel('Calibration JSON');
  await sees(text, 'the calibration text');
  await page.waitForFunction(() => document.querySelector('[aria-label="Calibration JSON"]')?.value.includes('devices'));
  const original = await text.inputValue();
  await text.fill('{"devices": 5}');
  const bad = await click_for_response(page, calibration.getByRole('button', { name: 'Save calibration' }), 'PUT', /^\/api\/stations\/\d+\/calibration$/);
  assert.equal(bad.status(), 422);
  await sees(calibration.getByRole('alert').filter({ hasText: (await bad.json()).error }), 'why the calibration was refused');
  await text.fill(original);
  const saved = await click_for_response(page, calibration.getByRole('button', { name: 'Save calibration' }), 'PUT', /^\/api\/stations\/\d+\/calibration$/);
  assert.equal(saved.status(), 200, await saved.text());
  await sees(calibration.getByRole('status').filter({ hasText: 'Calibration saved.' }), 'the calibration saved');

  // The form edits the same calibration: the first device turned by a yaw of 90 degrees.
  const yaw = calibration.getByLabel('Yaw (°)').first();
  await yaw.fill('90');
  const turned = JSON.parse(await text.inputValue());
  const [w, , , z] = turned.devices[0].mapping.rotation;
  assert.ok(Math.abs(w - Math.SQRT1_2) < 1e-9 && Math.abs(z - Math.SQRT1_2) < 1e-9, `rotation ${turned.devices[0].mapping.rotation}`);
  await text.fill(original);
  assert.equal(await yaw.inputValue(), '0', 'the form follows the JSON');

  // What a station can run: Station 1 becomes a laparoscopy station and a bench again.
  const kind = page.getByLabel('Kind of Station 1', { exact: true });
  assert.equal(await kind.inputValue(), 'bench', 'the demo Station 1 is a bench station');
  for (const value of ['laparoscopy', 'bench']) {
    const [changed] = await Promise.all([
      page.waitForResponse((r) => r.request().method() === 'PATCH' && /^\/api\/stations\/\d+$/.test(new URL(r.url()).pathname)),
      kind.selectOption(value),
    ]);
    assert.equal(changed.status(), 200, await changed.text());
    await page.waitForFunction((v) => document.querySelector('[aria-label="Kind of Station 1"]')?.value === v, value);
  }

  // The demo trainee is taught by the demo instructor; take that away and give it back.
  await admin_area(page, 'Users');
  const users = await page.evaluate(async () => (await fetch('/api/users')).json());
  const trainee = users.find((u) => u.username === demo.trainee.username);
  const picker = page.getByTestId(`instructor-picker-${trainee.id}`);
  const ines = picker.getByLabel('Ines Instructor');
  assert.equal(await ines.isChecked(), true, 'the demo instructor teaches the demo trainee');
  const removed = await click_for_response(page, ines, 'PUT', new RegExp(`^/api/users/${trainee.id}/instructors$`));
  assert.equal(removed.status(), 200);
  assert.deepEqual(removed.request().postDataJSON(), { instructor_ids: [] });
  const restored = await click_for_response(page, ines, 'PUT', new RegExp(`^/api/users/${trainee.id}/instructors$`));
  assert.equal(restored.status(), 200);
  assert.equal((await restored.json()).instructor_ids.length, 1);

  // Every change is in the audit log, with what it changed: a station's kind before and after.
  await admin_area(page, 'Audit log');
  const audit = page.getByTestId('audit-log');
  await audit.getByRole('button', { name: 'Refresh' }).click();
  const kind_row = audit.getByRole('row').filter({ hasText: 'station.update' }).first();
  await sees(kind_row.filter({ hasText: 'kind: “laparoscopy” → “bench”' }), 'the kind change in the audit log');
  for (const action of ['curriculum.import', 'curriculum.update', 'station.calibrate', 'user.instructors']) {
    await sees(audit.getByRole('row').filter({ hasText: action }), `"${action}" in the audit log`);
  }
  await snap(page, 'admin-home');
});

scenario('keyboard and narrow screens: the skip link, a title per page, the calendar at 800 px', async (page) => {
  await page.goto('/login');
  await page.waitForFunction(() => document.title === 'Log in · Incise');

  assert.equal((await log_in(page, demo.trainee)).status(), 200);
  await page.waitForURL('**/trainee');
  await page.waitForFunction(() => document.title === 'My training · Incise');

  // On a page as it opens, the first Tab reaches "Skip to content"; Enter moves the focus to the
  // page's main content.
  await page.goto('/trainee');
  await page.waitForFunction(() => document.title === 'My training · Incise');
  await page.keyboard.press('Tab');
  const skip = page.getByRole('link', { name: 'Skip to content' });
  assert.ok(await skip.evaluate((a) => a === document.activeElement), 'the skip link is focused first');
  await page.keyboard.press('Enter');
  assert.equal(await page.evaluate(() => document.activeElement?.id), 'main');

  // At 800 px the week's calendar fits or scrolls in its own box: the page itself does not.
  await page.setViewportSize({ width: 800, height: 900 });
  const calendar = region(page, 'Station calendar');
  await sees(calendar.getByTestId('booking-calendar'), 'the station calendar');
  await sees(calendar.getByRole('button', { name: /^Book / }).first(), 'bookable slots');
  const overflow = await page.evaluate(() => document.documentElement.scrollWidth - document.documentElement.clientWidth);
  assert.ok(overflow <= 0, `the page is ${overflow} px wider than the 800 px window`);
  await snap(page, 'calendar-800px');

  await page.goto('/admin');
  await page.waitForFunction(() => document.title === 'Access denied · Incise');
});

scenario('an admin disables a user, who can no longer log in, resets a password, and reads before and after in the audit log', async (page) => {
  assert.equal((await log_in(page, demo.admin)).status(), 200);
  await page.waitForURL('**/admin/users');
  // A trainee of this scenario's own, so that the demo logins stay as they are.
  const username = `dis-${Date.now().toString(36)}`;
  const password = 'first-password-1';
  const created = await api_call(page, 'POST', '/api/users', { username, password, role: 'trainee', display_name: 'Dana Disabled' });
  assert.equal(created.status, 201, JSON.stringify(created.body));
  await page.reload();
  const users = region(page, 'Users');
  const row = users.getByRole('row').filter({ has: page.getByRole('cell', { name: username, exact: true }) });
  await sees(row.getByTestId(`user-${username}-status`).filter({ hasText: 'Active' }), 'the new trainee active');

  const disabled = await click_for_response(page, row.getByRole('button', { name: 'Disable' }), 'PATCH', /^\/api\/users\/\d+$/);
  assert.equal(disabled.status(), 200, await disabled.text());
  await sees(row.getByTestId(`user-${username}-status`).filter({ hasText: 'Disabled' }), 'the trainee shown disabled');
  await sees(row.getByRole('status').filter({ hasText: `${username} is disabled and logged out.` }), 'the confirmation');

  // The password: a temporary one the trainee must replace at their next login.
  await row.getByRole('button', { name: 'Reset password' }).click();
  await row.getByLabel('Temporary password').fill('temporary-pass-2');
  const reset = await click_for_response(page, row.getByRole('button', { name: 'Set password', exact: true }), 'POST', /^\/api\/users\/\d+\/password$/);
  assert.equal(reset.status(), 200, await reset.text());
  await sees(row.getByRole('status').filter({ hasText: `${username} must choose a new password at their next login.` }), 'the reset confirmed');

  // A station retired: kept in the list, marked, and no longer offered for booking.
  const station = await api_call(page, 'POST', '/api/stations', { name: `Old bench ${username}`, location: 'Basement' });
  assert.equal(station.status, 201, JSON.stringify(station.body));
  const station_id = station.body.station.id;
  await admin_area(page, 'Stations');
  const retired = await click_for_response(page, page.getByTestId(`station-${station_id}-retire`), 'PATCH', /^\/api\/stations\/\d+$/);
  assert.equal(retired.status(), 200, await retired.text());
  await sees(page.getByTestId(`station-${station_id}-state`).filter({ hasText: 'Retired' }), 'the station shown retired');
  await sees(page.getByTestId(`station-${station_id}-retire`).filter({ hasText: 'Return to service' }), 'the way back');

  // Before and after, and never the password, in the audit log.
  await admin_area(page, 'Audit log');
  const audit = page.getByTestId('audit-log');
  await sees(audit.getByRole('row').filter({ hasText: 'user.disable' }).filter({ hasText: username }).filter({ hasText: 'disabled: false → true' }), 'the disabling with before and after');
  await sees(audit.getByRole('row').filter({ hasText: 'user.password_reset' }).filter({ hasText: 'must_change_password: false → true' }), 'the reset with before and after');
  await sees(audit.getByRole('row').filter({ hasText: 'station.retire' }).filter({ hasText: 'retired: false → true' }), 'the retirement with before and after');
  assert.equal(await audit.getByText('temporary-pass-2').count(), 0, 'no password in the audit log');
  await snap(page, 'admin-audit');

  // The disabled trainee cannot log in, even with the right password.
  await click_for_response(page, page.getByRole('button', { name: 'Log out' }), 'POST', /^\/api\/logout$/);
  const refused = await log_in(page, { username, password: 'temporary-pass-2' });
  assert.equal(refused.status(), 403);
  await sees(page.getByRole('alert').filter({ hasText: 'this account is disabled; ask an admin' }), 'why the login was refused');

  // Enabled again, they log in with the temporary password and must choose their own first.
  assert.equal((await log_in(page, demo.admin)).status(), 200);
  await page.waitForURL('**/admin/users');
  const again = region(page, 'Users').getByRole('row').filter({ has: page.getByRole('cell', { name: username, exact: true }) });
  const enabled = await click_for_response(page, again.getByRole('button', { name: 'Enable' }), 'PATCH', /^\/api\/users\/\d+$/);
  assert.equal(enabled.status(), 200);
  await click_for_response(page, page.getByRole('button', { name: 'Log out' }), 'POST', /^\/api\/logout$/);
  assert.equal((await log_in(page, { username, password: 'temporary-pass-2' })).status(), 200);
  await page.waitForURL('**/password');
  await sees(page.getByTestId('password-reset-notice'), 'the notice to choose a new password');
  assert.equal((await api_call(page, 'GET', '/api/bookings')).status, 403, 'nothing else answers before the change');
  await page.getByLabel('Temporary password').fill('temporary-pass-2');
  await page.getByLabel('New password', { exact: true }).fill('my-own-password-3');
  await page.getByLabel('New password again').fill('my-own-password-3');
  const changed = await click_for_response(page, page.getByRole('button', { name: 'Save the new password' }), 'POST', /^\/api\/me\/password$/);
  assert.equal(changed.status(), 200, await changed.text());
  await page.waitForURL('**/trainee');
  await sees(page.getByRole('heading', { name: 'My training' }), "the trainee's page after the change");
  const station_choice = page.getByRole('form', { name: 'Book a slot' }).getByLabel('Station', { exact: true });
  await station_choice.locator('option', { hasText: 'Station 1' }).waitFor({ state: 'attached' });
  const offered = await station_choice.locator('option').allTextContents();
  assert.ok(offered.length > 0 && !offered.some((o) => o.startsWith('Old bench')), `the retired station is not offered: ${offered}`);
});
