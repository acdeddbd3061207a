// Browser test of tissue calibration (docs/calibration.md) against the real incise-server
// (node --test): an admin runs a calibration job from the "Tissue calibration" page on the cube's
// example data, after a broken file is refused with its line; sees the fit and saves it as a
// material; a task of the curriculum names it, and the page shows the task using it. Needs
// web/dist and the server binary; see support.mjs.
import assert from 'node:assert/strict';
import { api_call, browser_suite, click_for_response, demo, log_in, sees, snap } from './support.mjs';

const { scenario } = browser_suite({ time_zone: 'Europe/Rome' });

const cube = 'scenes/calibration/cube.json';

scenario(
  'an admin fits the cube to its probe data, saves the material and a task uses it',
  async (page) => {
    const login = await log_in(page, demo.admin);
    assert.equal(login.status(), 200);
    await page.goto('/admin/calibration');
    const form = page.getByRole('form', { name: 'New calibration' });
    await sees(form, 'the calibration form');
    await form.getByLabel('Scene').selectOption(cube);
    await form.getByLabel('Method').selectOption('lm');
    await form.getByLabel('Parameters').selectOption('label');
    await form.getByLabel('Budget (simulations)').fill('200');

    // The example data the page offers for the scene, as a download.
    const example_link = form.getByTestId('calibration-example');
    await sees(example_link, 'the example data link');
    const example = await page.evaluate(async (href) => (await fetch(href)).text(), await example_link.getAttribute('href'));
    assert.ok(example.startsWith('time_s,contact,x,y,z,dir_x,dir_y,dir_z,force_n\n'), example.slice(0, 80));

    // A force that is a word: refused with its line, nothing queued.
    const lines = example.split('\n');
    lines[2] = lines[2].replace(/,[^,]*$/, ',abc');
    const file_input = form.getByLabel('Data file (CSV)');
    await file_input.setInputFiles({ name: 'broken.csv', mimeType: 'text/csv', buffer: Buffer.from(lines.join('\n')) });
    const refused = await click_for_response(page, form.getByRole('button', { name: 'Run calibration' }), 'POST', /^\/api\/calibration\/jobs$/);
    assert.equal(refused.status(), 422);
    assert.equal((await refused.json()).error, "data: line 3: force_n 'abc' is not a number");
    await sees(form.getByRole('alert').filter({ hasText: "data: line 3: force_n 'abc' is not a number" }), 'the line of the problem');
    assert.deepEqual((await api_call(page, 'GET', '/api/calibration/jobs')).body.jobs, [], 'nothing queued');

    // The example itself: a job that runs in the background to its fit.
    await file_input.setInputFiles({ name: 'cube_pushes.csv', mimeType: 'text/csv', buffer: Buffer.from(example) });
    await sees(form.getByTestId('calibration-data-name').filter({ hasText: 'cube_pushes.csv' }), 'the chosen file');
    const created = await click_for_response(page, form.getByRole('button', { name: 'Run calibration' }), 'POST', /^\/api\/calibration\/jobs$/);
    assert.equal(created.status(), 201, await created.text());
    const { job } = await created.json();
    assert.deepEqual(created.request().postDataJSON(), {
      scene: cube,
      method: 'lm',
      per: 'label',
      budget: 200,
      data: example,
      data_name: 'cube_pushes.csv',
    });
    const jobs = page.getByTestId('calibration-jobs');
    // A second here; a loaded machine may take longer than sees() waits.
    await jobs.getByTestId(`calibration-job-${job.id}-status`).filter({ hasText: 'Done' }).waitFor({ state: 'visible', timeout: 60_000 });
    const result = page.getByTestId('calibration-result');
    await sees(result.filter({ has: page.getByTestId('calibration-result-status').filter({ hasText: 'Done' }) }), 'the result panel');
    // The data came from a 3.6 kPa cube; the scene said 2.4 kPa.
    const values = result.getByTestId('calibration-values');
    await sees(
      values.getByRole('row').filter({ hasText: 'E, label 0' }).filter({ hasText: '2.40 kPa' }).filter({ hasText: '3.60 kPa' }),
      'E from 2.40 to 3.60 kPa',
    );
    await sees(result.getByTestId('calibration-misfit').filter({ hasText: '→' }), 'the misfit before and after');
    await sees(result.getByTestId('calibration-fit'), 'the measured and fitted curves');
    await snap(page, 'admin-tissue-calibration');

    // Saved as a named material.
    const save = result.getByRole('form', { name: 'Save material' });
    await save.getByLabel('Material name').fill('Calibrated cube');
    const saved = await click_for_response(page, save.getByRole('button', { name: 'Save material' }), 'POST', /^\/api\/materials$/);
    assert.equal(saved.status(), 201, await saved.text());
    const { material } = await saved.json();
    // One line says so, in place of the form.
    await sees(result.getByTestId('calibration-saved-as').filter({ hasText: 'Saved as material “Calibrated cube”.' }), 'the material saved');
    assert.equal(await save.count(), 0, 'the save form gone');
    const materials = page.getByTestId('materials');
    await sees(materials.getByRole('row').filter({ hasText: 'Calibrated cube' }), 'the material listed');

    // The palpation task names it in the curriculum (the Curricula page's editor)...
    await page.goto('/admin/curricula');
    const editor = page.getByTestId('curriculum-editor');
    const json_text = editor.getByLabel('Curriculum JSON');
    await page.waitForFunction(() => document.querySelector('[aria-label="Curriculum JSON"]')?.value.includes('palpation'));
    const definition = JSON.parse(await json_text.inputValue());
    assert.equal(definition.modules[0].tasks[0].key, 'palpation');
    definition.modules[0].tasks[0].material = 'Calibrated cube';
    await json_text.fill(JSON.stringify(definition, null, 2));
    const kept = await click_for_response(page, editor.getByRole('button', { name: 'Save curriculum' }), 'PUT', /^\/api\/curricula\/\d+$/);
    assert.equal(kept.status(), 200, await kept.text());

    // ...and the calibration page shows the task using it.
    await page.goto('/admin/calibration');
    await sees(page.getByTestId(`material-${material.id}-tasks`).filter({ hasText: 'palpation' }), 'the task that uses the material');
  },
  { timeout_ms: 90_000 },
);
