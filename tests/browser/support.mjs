// Shared by the browser tests (node --test): starts the real incise-server (and, on request, the
// real incise-agent) with a fresh data directory, launches Chromium, and runs each scenario in a
// fresh browser context. Needs web/dist (npm run build in web/), the server binary
// (INCISE_SERVER_BIN, default build/bin/incise-server), for the agent INCISE_AGENT_BIN (default:
// incise-agent next to the server binary), and Chromium (INCISE_CHROMIUM, default /usr/bin/chromium).
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import os from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { fileURLToPath } from 'node:url';

export const repo = fileURLToPath(new URL('../../', import.meta.url));
const output_dir = path.join(repo, 'tests/browser/output');
const require = createRequire(new URL('../../web/package.json', import.meta.url));
const { chromium } = require('playwright-core');

const server_bin = path.resolve(repo, process.env.INCISE_SERVER_BIN ?? 'build/bin/incise-server');
const agent_bin = path.resolve(repo, process.env.INCISE_AGENT_BIN ?? path.join(path.dirname(server_bin), 'incise-agent'));
const web_dist = path.join(repo, 'web/dist');
const chromium_path = process.env.INCISE_CHROMIUM ?? '/usr/bin/chromium';

/** The logins and station token that `incise-server --demo` creates. */
export const demo = {
  admin: { username: 'admin', password: 'incise-admin-demo' },
  instructor: { username: 'instructor', password: 'incise-instructor-demo' },
  trainee: { username: 'trainee', password: 'incise-trainee-demo' },
  resident: { username: 'resident', password: 'incise-resident-demo' },
  station_token: 'incise-demo-station-token',
  surgical_station_token: 'incise-demo-surgical-station-token',
  arthroscopy_station_token: 'incise-demo-arthroscopy-station-token',
};

/**
 * Registers before/after hooks that start the server (and a station's agent when `with_agent`:
 * Station 1's with its built-in script, or `agent` = `{ token, args }`) and a browser, and
 * returns `scenario(name, body, { timeout_ms })`, which runs `body(page, env)` in a fresh context
 * whose browser runs in `time_zone`. `env.server` is `{ url, log }`. On failure a screenshot and
 * the processes' logs go to tests/browser/output/.
 */
export function browser_suite({ time_zone, with_agent = false, agent = {} }) {
  const env = { server: null, agent: null, browser: null, data_dir: null };

  before(async () => {
    assert.ok(fs.existsSync(server_bin), `server binary not found at ${server_bin}; build it first`);
    assert.ok(fs.existsSync(path.join(web_dist, 'index.html')), `${web_dist} is missing; run "npm run build" in web/`);
    if (with_agent) assert.ok(fs.existsSync(agent_bin), `agent binary not found at ${agent_bin}; build it first`);
    env.data_dir = fs.mkdtempSync(path.join(os.tmpdir(), 'incise-browser-'));
    env.server = await start_server(env.data_dir);
    if (with_agent) env.agent = await start_agent(env.server.url, agent);
    env.browser = await chromium.launch({
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
    await env.browser?.close();
    if (env.agent) await stop_process(env.agent.process);
    if (env.server) await stop_process(env.server.process);
    if (env.data_dir) fs.rmSync(env.data_dir, { recursive: true, force: true });
  });

  function scenario(name, body, { timeout_ms = 45_000 } = {}) {
    test(name, { timeout: timeout_ms }, async () => {
      const context = await env.browser.newContext({
        baseURL: env.server.url,
        locale: 'en-GB',
        timezoneId: time_zone,
        viewport: { width: 1366, height: 800 },
      });
      context.setDefaultTimeout(8_000);
      const page = await context.newPage();
      const page_errors = [];
      page.on('pageerror', (error) => page_errors.push(error.message));
      try {
        await body(page, env);
        assert.deepEqual(page_errors, [], 'the page threw uncaught errors');
      } catch (error) {
        fs.mkdirSync(output_dir, { recursive: true });
        const slug = name.replace(/[^a-z0-9]+/gi, '-').toLowerCase();
        await page.screenshot({ path: path.join(output_dir, `${slug}.png`), fullPage: true }).catch(() => {});
        const logs = [env.server, env.agent].filter(Boolean).map((p) => p.log.stderr + p.log.stdout);
        fs.writeFileSync(path.join(output_dir, `${slug}.server.log`), logs.join('\n--- agent ---\n'));
        throw error;
      } finally {
        await context.close();
      }
    });
  }

  return { env, scenario };
}

/**
 * Spawns `bin` and resolves once its stdout or stderr matches `ready` (with the match), or rejects
 * with its output when it exits or stays silent for 20 s.
 */
function start_process(bin, args, ready, what, env = process.env) {
  const child = spawn(bin, args, { cwd: repo, env, stdio: ['ignore', 'pipe', 'pipe'] });
  const log = { stdout: '', stderr: '' };

  return new Promise((resolve, reject) => {
    let started = false;
    const fail = (why) => {
      clearTimeout(timer);
      child.kill('SIGKILL');
      reject(new Error(`${why}\n--- ${what} stderr ---\n${log.stderr}\n--- ${what} stdout ---\n${log.stdout}`));
    };
    const timer = setTimeout(() => fail(`${what} did not report ready (${ready}) within 20 s`), 20_000);
    child.on('error', (error) => fail(`could not start ${bin}: ${error.message}`));
    child.on('exit', (code, signal) => fail(`${what} exited early (code ${code}, signal ${signal})`));
    for (const stream of ['stdout', 'stderr']) {
      child[stream].setEncoding('utf8');
      child[stream].on('data', (chunk) => {
        log[stream] += chunk;
        const match = started ? null : ready.exec(log[stream]);
        if (match) {
          started = true;
          clearTimeout(timer);
          child.removeAllListeners('exit');
          resolve({ process: child, log, match });
        }
      });
    }
  });
}

async function start_server(data_dir) {
  const args = ['--port', '0', '--host', '127.0.0.1', '--data', data_dir, '--web', web_dist, '--demo'];
  const started = await start_process(server_bin, args, /incise-server: listening on (http:\/\/[\d.]+:\d+)/, 'incise-server');
  return { process: started.process, log: started.log, url: started.match[1] };
}

/**
 * A demo station's agent (Station 1's with its built-in simulated device unless `token` and
 * `args` say otherwise); resolves once the server welcomed it.
 */
async function start_agent(server_url, { token = demo.station_token, args: extra = [] } = {}) {
  const agent_url = `${server_url.replace(/^http/, 'ws')}/agent`;
  const args = ['--server', agent_url, ...extra];
  // The token goes in the environment: the agent refuses it on its command line.
  const env = { ...process.env, INCISE_STATION_TOKEN: token };
  const started = await start_process(agent_bin, args, /incise-agent: connected to \S+ as station (\d+)/, 'incise-agent', env);
  return { process: started.process, log: started.log, station_id: Number(started.match[1]) };
}

async function stop_process(child) {
  if (child.exitCode !== null || child.signalCode !== null) return;
  const exited = new Promise((resolve) => child.once('exit', resolve));
  child.kill('SIGTERM');
  const timer = setTimeout(() => child.kill('SIGKILL'), 5_000);
  await exited;
  clearTimeout(timer);
}

/**
 * Saves a full-page screenshot of what the page shows now to tests/browser/output/pages/NAME.jpg:
 * every page the tests visit, made fresh by every run (docs/tour/ holds copies for the README).
 */
export async function snap(page, name) {
  const dir = path.join(output_dir, 'pages');
  fs.mkdirSync(dir, { recursive: true });
  // Let charts and the picture settle after the last change.
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(dir, `${name}.jpg`), type: 'jpeg', quality: 70, fullPage: true });
}

/** Waits until `locator` is visible: the assertion that a person can see it. */
export async function sees(locator, what) {
  try {
    await locator.first().waitFor({ state: 'visible' });
  } catch (error) {
    throw new assert.AssertionError({ message: `expected to see ${what}: ${error.message.split('\n')[0]}` });
  }
}

/** Clicks `button` and returns the API response to `method path` that the click caused. */
export async function click_for_response(page, button, method, path_pattern) {
  const [response] = await Promise.all([
    page.waitForResponse((r) => r.request().method() === method && path_pattern.test(new URL(r.url()).pathname)),
    button.click(),
  ]);
  return response;
}

/**
 * A logged-in trainee walks up to `station_name` (the only station online, so preselected under
 * "Train now"), books it from now, picks the task `task_key`, sees `instructions` and starts it.
 * Returns the session the server started, the page on its live view.
 */
export async function walk_up_and_start(page, station_name, task_key, instructions, offered = null) {
  const stations = (await api_call(page, 'GET', '/api/stations')).body;
  const station = stations.find((s) => s.name === station_name);
  assert.ok(station?.online, `the ${station_name}'s agent is connected: ${JSON.stringify(stations)}`);
  const train = region(page, 'Train now');
  const walk_up = train.getByRole('form', { name: 'Walk up to a station' });
  await sees(walk_up, 'the walk-up form');
  assert.equal(await walk_up.getByLabel('Station').inputValue(), String(station.id), 'the online station is preselected');
  const booked = await click_for_response(page, walk_up.getByRole('button', { name: /^Book from / }), 'POST', /^\/api\/bookings$/);
  assert.equal(booked.status(), 201, await booked.text());
  const start_form = train.getByRole('form', { name: `Start a session at ${station_name}` });
  await sees(start_form, `a form to start a session at the ${station_name}`);
  await start_form.getByLabel('Task').selectOption(task_key);
  if (offered) {
    // Only the tasks this kind of station can run are offered (the server's list).
    const keys = await start_form.getByLabel('Task').locator('option').evaluateAll((options) => options.map((o) => o.value));
    assert.deepEqual(keys, offered, `the tasks offered at the ${station_name}`);
  }
  await sees(start_form.filter({ hasText: instructions }), `the instructions of ${task_key}`);
  const started = await click_for_response(page, start_form.getByRole('button', { name: 'Start session' }), 'POST', /^\/api\/sessions$/);
  assert.equal(started.status(), 201, await started.text());
  const session = await started.json();
  await page.waitForURL(`**/sessions/${session.id}`);
  return session;
}

export async function log_in(page, { username, password }) {
  await page.goto('/login');
  await page.getByLabel('Username', { exact: true }).fill(username);
  await page.getByLabel('Password', { exact: true }).fill(password);
  return click_for_response(page, page.getByRole('button', { name: 'Log in' }), 'POST', /^\/api\/login$/);
}

export function region(page, name) {
  return page.getByRole('region', { name, exact: true });
}

/** Calls the API from the page, with its login cookie. */
export async function api_call(page, method, path, body) {
  return page.evaluate(
    async ({ method, path, body }) => {
      const init = { method, headers: { Accept: 'application/json' }, credentials: 'same-origin' };
      if (body !== undefined) {
        init.headers['Content-Type'] = 'application/json';
        init.body = JSON.stringify(body);
      }
      const response = await fetch(path, init);
      const text = await response.text();
      return { status: response.status, body: text ? JSON.parse(text) : null };
    },
    { method, path, body },
  );
}

/**
 * The canvas' last drawn frame and its simulated time (its data-frame and data-sim-time), and the
 * grey level of a 64 x 48 grid of its pixels, read back with getImageData.
 */
export async function canvas_state(page, test_id) {
  return page.evaluate((test_id) => {
    const canvas = document.querySelector(`[data-testid="${test_id}"]`);
    const { data } = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height);
    const grid = [];
    for (let gy = 0; gy < 48; gy++) {
      for (let gx = 0; gx < 64; gx++) {
        const x = Math.floor(((gx + 0.5) * canvas.width) / 64);
        const y = Math.floor(((gy + 0.5) * canvas.height) / 48);
        const i = 4 * (y * canvas.width + x);
        grid.push(0.299 * data[i] + 0.587 * data[i + 1] + 0.114 * data[i + 2]);
      }
    }
    return { frame: Number(canvas.dataset.frame), sim_time: Number(canvas.dataset.simTime), grid };
  }, test_id);
}

/**
 * Waits until `test_id`'s canvas has drawn a frame after `after_frame` whose simulated time lies in
 * [time_min, time_max] (either bound may be left out); says what it waited for when it times out.
 */
export async function wait_for_canvas(page, test_id, { after_frame = 0, time_min = null, time_max = null }, what, timeout = 15_000) {
  try {
    await page.waitForFunction(
      ({ test_id, after_frame, time_min, time_max }) => {
        const canvas = document.querySelector(`[data-testid="${test_id}"]`);
        const frame = Number(canvas?.dataset.frame);
        const sim_time = Number(canvas?.dataset.simTime);
        return frame > after_frame && (time_min === null || sim_time >= time_min) && (time_max === null || sim_time <= time_max);
      },
      { test_id, after_frame, time_min, time_max },
      { timeout, polling: 50 },
    );
  } catch (error) {
    const state = await canvas_state(page, test_id).catch(() => null);
    throw new assert.AssertionError({
      message: `expected ${what}; the canvas shows frame ${state?.frame}, sim time ${state?.sim_time}: ${error.message.split('\n')[0]}`,
    });
  }
}

/** A row of the live or replay metrics list, by its key (data-testid "metric-<key>"). */
export function metric(page, key) {
  return page.getByTestId(`metric-${key}`);
}
