// Browser test of the dashboard against the real incise-server (node --test).
// Each scenario asserts what a person sees, and the API status behind it where that matters.
// Needs web/dist (npm run build in web/) and the server binary
// (INCISE_SERVER_BIN, default build/bin/incise-server).
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import os from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { fileURLToPath } from 'node:url';

const repo = fileURLToPath(new URL('../../', import.meta.url));
const output_dir = path.join(repo, 'tests/browser/output');
const require = createRequire(new URL('../../web/package.json', import.meta.url));
const { chromium } = require('playwright-core');

const server_bin = path.resolve(repo, process.env.INCISE_SERVER_BIN ?? 'build/bin/incise-server');
const web_dist = path.join(repo, 'web/dist');
const chromium_path = process.env.INCISE_CHROMIUM ?? '/usr/bin/chromium';

const demo = {
  admin: { username: 'admin', password: 'incise-admin-demo' },
  instructor: { username: 'instructor', password: 'incise-instructor-demo' },
  trainee: { username: 'trainee', password: 'incise-trainee-demo' },
};

// The browser runs in a zone with a half-hour offset and no daylight saving, so that the local
// time shown and the UTC time sent are different and predictable.
const time_zone = 'Asia/Kolkata'; // UTC+05:30

let server; // { process, url, log }
let browser;
let data_dir;

before(async () => {
  assert.ok(fs.existsSync(server_bin), `server binary not found at ${server_bin}; build it first`);
  assert.ok(fs.existsSync(path.join(web_dist, 'index.html')), `${web_dist} is missing; run "npm run build" in web/`);
  data_dir = fs.mkdtempSync(path.join(os.tmpdir(), 'incise-browser-'));
  server = await start_server();
  browser = await chromium.launch({
    executablePath: chromium_path,
    args: [
      '--headless',
      '--no-sandbox',
      '--disable-gpu',
      '--disable-quic',
      '--no-first-run',
      '--disable-background-networking',
      '--disable-component-update',
      '--disable-sync',
    ],
  });
});

after(async () => {
  await browser?.close();
  if (server) await stop_server(server.process);
  if (data_dir) fs.rmSync(data_dir, { recursive: true, force: true });
});

function start_server() {
  const args = ['--port', '0', '--host', '127.0.0.1', '--data', data_dir, '--web', web_dist, '--demo'];
  const child = spawn(server_bin, args, { cwd: repo, stdio: ['ignore', 'pipe', 'pipe'] });
  const log = { stdout: '', stderr: '' };
  child.stdout.setEncoding('utf8');
  child.stderr.setEncoding('utf8');
  child.stderr.on('data', (chunk) => (log.stderr += chunk));

  return new Promise((resolve, reject) => {
    const fail = (why) => {
      clearTimeout(timer);
      child.kill('SIGKILL');
      reject(new Error(`${why}\n--- server stderr ---\n${log.stderr}\n--- server stdout ---\n${log.stdout}`));
    };
    const timer = setTimeout(() => fail('incise-server did not report "listening" within 20 s'), 20_000);
    child.on('error', (error) => fail(`could not start ${server_bin}: ${error.message}`));
    child.on('exit', (code, signal) => fail(`incise-server exited early (code ${code}, signal ${signal})`));
    child.stdout.on('data', (chunk) => {
      log.stdout += chunk;
      const match = /incise-server: listening on (http:\/\/[\d.]+:\d+)/.exec(log.stdout);
      if (match) {
        clearTimeout(timer);
        child.removeAllListeners('exit');
        resolve({ process: child, url: match[1], log });
      }
    });
  });
}

async function stop_server(child) {
  if (child.exitCode !== null || child.signalCode !== null) return;
  const exited = new Promise((resolve) => child.once('exit', resolve));
  child.kill('SIGTERM');
  const timer = setTimeout(() => child.kill('SIGKILL'), 5_000);
  await exited;
  clearTimeout(timer);
}

/**
 * Runs `body` with a fresh browser context (no cookies shared between scenarios). On failure it
 * saves a screenshot and the server's log to tests/browser/output/ and rethrows.
 */
function scenario(name, body) {
  test(name, { timeout: 45_000 }, async () => {
    const context = await browser.newContext({
      baseURL: server.url,
      locale: 'en-GB',
      timezoneId: time_zone,
      viewport: { width: 1366, height: 800 },
    });
    context.setDefaultTimeout(8_000);
    const page = await context.newPage();
    const page_errors = [];
    page.on('pageerror', (error) => page_errors.push(error.message));
    try {
      await body(page);
      assert.deepEqual(page_errors, [], 'the page threw uncaught errors');
    } catch (error) {
      fs.mkdirSync(output_dir, { recursive: true });
      const slug = name.replace(/[^a-z0-9]+/gi, '-').toLowerCase();
      await page.screenshot({ path: path.join(output_dir, `${slug}.png`), fullPage: true }).catch(() => {});
      fs.writeFileSync(path.join(output_dir, `${slug}.server.log`), server.log.stderr + server.log.stdout);
      throw error;
    } finally {
      await context.close();
    }
  });
}

/** Waits until `locator` is visible: the assertion that a person can see it. */
async function sees(locator, what) {
  try {
    await locator.first().waitFor({ state: 'visible' });
  } catch (error) {
    throw new assert.AssertionError({ message: `expected to see ${what}: ${error.message.split('\n')[0]}` });
  }
}

/** Clicks `button` and returns the API response to `method path` that the click caused. */
async function click_for_response(page, button, method, path_pattern) {
  const [response] = await Promise.all([
    page.waitForResponse((r) => r.request().method() === method && path_pattern.test(new URL(r.url()).pathname)),
    button.click(),
  ]);
  return response;
}

async function log_in(page, { username, password }) {
  await page.goto('/login');
  await page.getByLabel('Username', { exact: true }).fill(username);
  await page.getByLabel('Password', { exact: true }).fill(password);
  const response = await click_for_response(page, page.getByRole('button', { name: 'Log in' }), 'POST', /^\/api\/login$/);
  return response;
}

/** "YYYY-MM-DD" of tomorrow in the browser's zone. */
function tomorrow_in_zone() {
  return new Intl.DateTimeFormat('en-CA', { timeZone: time_zone }).format(new Date(Date.now() + 24 * 3600 * 1000));
}

function region(page, name) {
  return page.getByRole('region', { name, exact: true });
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
  await page.waitForURL('**/admin');

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
  await sees(users.getByRole('row').filter({ hasText: username }).filter({ hasText: 'Instructor' }), 'the new user in the users list');

  const duplicate = await create();
  assert.equal(duplicate.status(), 409);
  const { error: duplicate_message } = await duplicate.json();
  await sees(form.getByRole('alert').filter({ hasText: duplicate_message }), `the duplicate message "${duplicate_message}"`);
  assert.equal(await users.getByRole('row').filter({ hasText: username }).count(), 1, 'the user is listed once');

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
